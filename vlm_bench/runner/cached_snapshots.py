"""Episode snapshots as PNG bytes, rendered once and cached on disk across runs and models.

The cache key hashes everything that changes the pixels: the episode (layout, lighting, UAV
start), the image size, the labels flag, the simulator's source code, the world catalogue and
the MuJoCo version. Views are cached one file each, so a run showing fewer views reuses them.
The simulator is imported only when something must be rendered.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING

from vlm_bench.errors import ConfigError
from vlm_bench.resources import ground_truth_dir
from vlm_bench.storage import SnapshotCache
from vlm_bench.storage.provenance import folder_digest
from vlm_bench.types.episode import Episode

if TYPE_CHECKING:
    from vlm_bench.sim.render import SnapshotRenderer

_SIM_PACKAGE = Path(__file__).resolve().parent.parent / "sim"


@cache
def renderer_digest() -> str:
    """sha256 of what renders an episode: simulator sources, world catalogue, MuJoCo version."""
    try:
        mujoco_version = metadata.version("mujoco")
    except metadata.PackageNotFoundError:
        mujoco_version = "?"
    world = ground_truth_dir() / "world.json"
    parts = [
        folder_digest(_SIM_PACKAGE),
        mujoco_version,
        hashlib.sha256(world.read_bytes()).hexdigest() if world.exists() else "",
    ]
    return hashlib.sha256("|".join(parts).encode()).hexdigest()


def check_resolution(size: int) -> None:
    """Refuse a snapshot size the simulator's offscreen buffer cannot render.

    Raises:
        ConfigError: Names the size and the largest one.
    """
    from vlm_bench.sim.environment import OFFSCREEN_SIZE

    if size > OFFSCREEN_SIZE:
        raise ConfigError(
            f"resolution {size} exceeds the simulator's offscreen buffer; use at most "
            f"{OFFSCREEN_SIZE}"
        )


def snapshot_key(episode: Episode, size: int, labels: bool) -> str:
    """Content key of an episode's snapshots at one size."""
    payload = f"{renderer_digest()}|{size}|{labels}|{episode.model_dump_json()}"
    return hashlib.sha256(payload.encode()).hexdigest()


class SnapshotSource:
    """PNG snapshots per episode: from the cache, else rendered (one reused GL context, released
    by :meth:`close` or on leaving a ``with`` block)."""

    def __init__(
        self,
        views: Sequence[str],
        size: int,
        labels: bool = True,
        cache: SnapshotCache | None = None,
    ) -> None:
        self.views = list(views)
        self.size = size
        self.labels = labels
        self.cache = cache
        self.rendered = 0  # episodes rendered (not served from the cache)
        self._renderer: SnapshotRenderer | None = None
        self._last: tuple[str, dict[str, bytes]] | None = None

    def images(self, episode: Episode) -> dict[str, bytes]:
        """PNG bytes by view for the episode's start state."""
        key = snapshot_key(episode, self.size, self.labels)
        if self._last is not None and self._last[0] == key:
            return self._last[1]  # the other instruction variant of the same episode
        pngs: dict[str, bytes] = {}
        if self.cache is not None:
            for view in self.views:
                png = self.cache.get(key, view)
                if png is not None:
                    pngs[view] = png
        missing = [v for v in self.views if v not in pngs]
        if missing:
            fresh = self._render(episode, missing)
            if self.cache is not None:
                for view, png in fresh.items():
                    self.cache.put(key, view, png)
            pngs.update(fresh)
        out = {v: pngs[v] for v in self.views}
        self._last = (key, out)
        return out

    def _render(self, episode: Episode, views: list[str]) -> dict[str, bytes]:
        from vlm_bench.sim.render import SnapshotRenderer
        from vlm_bench.sim.snapshot_render import render_episode
        from vlm_bench.storage.png import to_png

        if self._renderer is None:
            self._renderer = SnapshotRenderer()
        self.rendered += 1
        images = render_episode(
            episode, views, self.size, labels=self.labels, renderer=self._renderer
        )
        return {view: to_png(images[view]) for view in views}

    def __enter__(self) -> SnapshotSource:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Release the GL context. Idempotent."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
