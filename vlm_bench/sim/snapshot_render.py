"""Four-view snapshots of an episode's start state, with set-of-marks labels, and sheets."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.errors import UnknownNameError
from vlm_bench.sim.cameras import task_objects
from vlm_bench.sim.constants import CAMERAS, DEFAULT_IMAGE_SIZE, THIRD_PERSON_CAMERAS
from vlm_bench.sim.labels import Box, draw_labels, project_points
from vlm_bench.sim.render import SnapshotRenderer, contact_sheet
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.types.episode import Episode, EpisodeObject

Views = dict[str, NDArray[np.uint8]]
AVOID_MARGIN = 3.0
"""px: a task object's box grows by this much, for its edge pixels and a tag's outline."""


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


def box_corners(obj: EpisodeObject) -> NDArray[np.float64]:
    """The eight corners of an object's box in the world (m)."""
    sx, sy, sz = object_kind(obj.kind).size
    yaw = math.radians(obj.yaw_deg)
    c, s = math.cos(yaw), math.sin(yaw)
    out = []
    for dx, dy, z in itertools.product((-sx / 2, sx / 2), (-sy / 2, sy / 2), (0.0, sz)):
        out.append((obj.pos[0] + c * dx - s * dy, obj.pos[1] + s * dx + c * dy, obj.pos[2] + z))
    return np.array(out)


def task_object_boxes(scene: Scene, view: str, size: int) -> list[Box]:
    """Pixel boxes of the task objects (:func:`~vlm_bench.sim.cameras.task_objects`) in
    ``view``: the bounds of each box's projected corners, which no label tag may cover."""
    wanted = set(task_objects(scene.episode))
    boxes: list[Box] = []
    for obj in scene.episode.objects:
        if obj.id not in wanted:
            continue
        pix, _ = project_points(scene.model, scene.data, view, box_corners(obj), size, size)
        if not np.isfinite(pix).all():
            continue
        (u0, v0), (u1, v1) = pix.min(axis=0) - AVOID_MARGIN, pix.max(axis=0) + AVOID_MARGIN
        boxes.append((float(u0), float(v0), float(u1), float(v1)))
    return boxes


def label_tags(
    scene: Scene, view: str, size: int
) -> tuple[list[tuple[str, tuple[float, float]]], list[Box]]:
    """The set-of-marks tags of ``view`` (each id at its point in the image, those in view)
    and the task objects' pixel boxes the tags keep off (:func:`task_object_boxes`)."""
    marks = _label_points(scene)
    if not marks:
        return [], []
    points = np.stack([p for _, p in marks])
    pix, visible = project_points(scene.model, scene.data, view, points, size, size)
    tags = [
        (text, (float(u), float(v)))
        for (text, _), (u, v), ok in zip(marks, pix, visible, strict=True)
        if ok
    ]
    return tags, task_object_boxes(scene, view, size)


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
    if labels and _label_points(scene):
        for view in THIRD_PERSON_CAMERAS:
            if view in images:
                tags, avoid = label_tags(scene, view, size)
                images[view] = draw_labels(images[view], tags, avoid)
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
