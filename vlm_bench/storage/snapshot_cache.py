"""A content-addressed cache of snapshot PNGs, shared by runs and models.

Images live at ``<root>/<key[:2]>/<key>/<view>.png``, where the key (computed by the caller)
hashes everything that changes the pixels. Writes go through a temporary file and a rename, so
concurrent runs never read half an image.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from vlm_bench.storage.jsonl import naming_the_file

_KEY = re.compile(r"^[0-9a-f]{16,64}$")
_VIEW = re.compile(r"^[a-z][a-z0-9_]*$")


def default_snapshot_cache(run_root: Path) -> Path:
    """``VLM_BENCH_SNAPSHOT_CACHE`` if set, else ``.snapshots`` beside the run folder.

    Runs kept side by side (``results/<run>/``) thus share ``results/.snapshots``.
    """
    override = os.environ.get("VLM_BENCH_SNAPSHOT_CACHE")
    return Path(override) if override else run_root.parent / ".snapshots"


class SnapshotCache:
    """PNG bytes by (content key, view)."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.hits = 0
        self.misses = 0

    def _path(self, key: str, view: str) -> Path:
        if not _KEY.match(key) or not _VIEW.match(view):
            raise ValueError(f"bad snapshot cache key {key!r} / view {view!r}")
        return self.root / key[:2] / key / f"{view}.png"

    def get(self, key: str, view: str) -> bytes | None:
        """The cached PNG, or None (a miss)."""
        path = self._path(key, view)
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            self.misses += 1
            return None
        self.hits += 1
        return data

    def put(self, key: str, view: str, png: bytes) -> None:
        """Store a PNG (atomically; concurrent writers of the same image are harmless)."""
        path = self._path(key, view)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{view}.{os.getpid()}.tmp")
        with naming_the_file(path):
            tmp.write_bytes(png)
        os.replace(tmp, path)
