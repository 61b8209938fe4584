"""The four camera views of an episode for the gallery, as JPEG bytes.

Views come from the run's snapshot cache (``.snapshots`` beside the run folder, or
``VLM_BENCH_SNAPSHOT_CACHE``), keyed as the run keyed them (episode, resolution, labels), so the
gallery shows the pixels the model saw. Views missing there (a run shown fewer views, a cache
deleted) are rendered when allowed, which needs MuJoCo. JPEG keeps a gallery of hundreds of
episodes to a few dozen megabytes.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

from PIL import Image

from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.run import RunManifest

if TYPE_CHECKING:
    from vlm_bench.runner.cached_snapshots import SnapshotSource

JPEG_QUALITY = 85


def to_jpeg(png: bytes) -> bytes:
    """PNG bytes re-encoded as JPEG."""
    with Image.open(io.BytesIO(png)) as image:
        out = io.BytesIO()
        image.convert("RGB").save(out, format="JPEG", quality=JPEG_QUALITY)
        return out.getvalue()


class EpisodeViews:
    """JPEG views by (task, seed) for one run; renders on a cache miss if ``render``."""

    def __init__(self, run_dir: Path, manifest: RunManifest, render: bool) -> None:
        from vlm_bench.storage import SnapshotCache, default_snapshot_cache

        self.manifest = manifest
        self.size = manifest.config.resolution
        self.labels = manifest.config.labels
        self.cache = SnapshotCache(default_snapshot_cache(run_dir.resolve()))
        self.render = render
        self.rendered = 0
        self._source: SnapshotSource | None = None

    def views(self, task_id: str, seed: int) -> dict[str, bytes]:
        """JPEG bytes of each view found (all four when rendering is allowed)."""
        from vlm_bench.episodes import get_episode
        from vlm_bench.runner.cached_snapshots import SnapshotSource, snapshot_key

        episode = get_episode(task_id, seed)
        key = snapshot_key(episode, self.size, self.labels)
        pngs: dict[str, bytes] = {
            v: png for v in VIEWS if (png := self.cache.get(key, v)) is not None
        }
        if len(pngs) < len(VIEWS) and self.render:
            if self._source is None:
                self._source = SnapshotSource(VIEWS, self.size, self.labels, self.cache)
            pngs = self._source.images(episode)
            self.rendered += 1
        return {v: to_jpeg(pngs[v]) for v in VIEWS if v in pngs}

    def close(self) -> None:
        """Release the renderer, if one was made."""
        if self._source is not None:
            self._source.close()
            self._source = None
