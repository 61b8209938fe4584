"""Four-view snapshots of an episode's start state, with set-of-marks labels, and sheets."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.errors import UnknownNameError
from vlm_bench.sim.constants import CAMERAS, DEFAULT_IMAGE_SIZE, THIRD_PERSON_CAMERAS
from vlm_bench.sim.labels import draw_labels, project_points
from vlm_bench.sim.render import SnapshotRenderer, contact_sheet
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.types.episode import Episode

Views = dict[str, NDArray[np.uint8]]


def check_views(views: Sequence[str]) -> list[str]:
    """Validate camera names; raises listing the valid ones."""
    for view in views:
        if view not in CAMERAS:
            raise UnknownNameError("camera view", view, CAMERAS)
    return list(views)


def _label_points(scene: Scene) -> list[tuple[str, NDArray[np.float64]]]:
    out = []
    for obj in scene.episode.objects:
        if obj.label:
            top = object_kind(obj.kind).size[2]
            out.append((obj.label, np.array(obj.pos) + np.array([0.0, 0.0, top + 0.02])))
    return out


def render_scene(
    scene: Scene,
    views: Sequence[str] = CAMERAS,
    size: int = DEFAULT_IMAGE_SIZE,
    labels: bool = True,
    renderer: SnapshotRenderer | None = None,
) -> Views:
    """Render ``views`` of a built scene; third-person views get set-of-marks labels."""
    own = renderer is None
    rend = renderer or SnapshotRenderer()
    try:
        images = rend.render_views(scene.model, scene.data, check_views(views), size)
    finally:
        if own:
            rend.close()
    marks = _label_points(scene) if labels else []
    if marks:
        points = np.stack([p for _, p in marks])
        for view in THIRD_PERSON_CAMERAS:
            if view not in images:
                continue
            pix, visible = project_points(scene.model, scene.data, view, points, size, size)
            tags = [
                (text, (float(u), float(v)))
                for (text, _), (u, v), ok in zip(marks, pix, visible, strict=True)
                if ok
            ]
            images[view] = draw_labels(images[view], tags)
    return images


def render_episode(
    episode: Episode,
    views: Sequence[str] = CAMERAS,
    size: int = DEFAULT_IMAGE_SIZE,
    labels: bool = True,
    renderer: SnapshotRenderer | None = None,
) -> Views:
    """Build the episode's scene and render its start-state snapshots."""
    return render_scene(build_scene(episode), views, size, labels, renderer)


def save_views(views: Views, out: Path, title: str | None = None) -> list[Path]:
    """Write ``<view>.png`` per view and a labelled 2×2 ``sheet.png``; returns the paths."""
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, image in views.items():
        path = out / f"{name}.png"
        Image.fromarray(image).save(path)
        paths.append(path)
    sheet = out / "sheet.png"
    contact_sheet(views, title=title, columns=2).save(sheet)
    paths.append(sheet)
    return paths


def episode_sheet(
    episodes: Sequence[Episode], view: str = "overhead", size: int = 224, columns: int = 6
) -> Image.Image:
    """One tile per episode (one view), or a 2×2 per episode with ``view='all'``."""
    views = list(CAMERAS) if view == "all" else check_views([view])
    renderer = SnapshotRenderer()
    tiles: dict[str, NDArray[np.uint8]] = {}
    try:
        for ep in episodes:
            images = render_episode(ep, views, size, renderer=renderer)
            key = f"{ep.task_id} (seed {ep.seed})" if ep.task_id in tiles else ep.task_id
            if len(views) == 1:
                tiles[key] = images[views[0]]
            else:
                tiles[key] = np.asarray(contact_sheet(images, title=None, columns=2))
    finally:
        renderer.close()
    return contact_sheet(tiles, title=f"{view} view", columns=columns)
