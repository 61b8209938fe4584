"""How large each task object appears in the third-person views, from geometry alone.

An episode is judged legible before any rendering (the episode generator redraws a layout that
is not, as it redraws one whose reach decision is too close to call): each task object
(:func:`~vlm_bench.sim.cameras.task_objects`) and the UAV lie wholly inside the ``overhead`` and
``side`` frames, and each task object is at least :data:`MIN_OBJECT_PX` across in one of them
(:data:`MIN_SMALL_PART_PX` for a part under :data:`SMALL_PART` in every dimension: bolts, nuts)
at :data:`~vlm_bench.sim.constants.DEFAULT_IMAGE_SIZE` px. "Across" is the shorter side of the
bounding box of the object's box projected by the camera, shrunk by :data:`BOX_TO_SHAPE` (an
object fills less of its image than its bounding box, and a cylinder less than its square
box); the rendered sizes (:mod:`vlm_bench.sim.footprint`) are tested against the same limits.
The overhead view looks down through the UAV: a task object it covers there
(:func:`uav_covers`) is judged by its side-view size alone (its recorded overhead size is still
the projection).
"""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.rules import rotate_xy
from vlm_bench.sim.cameras import (
    CameraView,
    framing_points,
    task_objects,
    third_person_views,
)
from vlm_bench.sim.constants import CAM_OVERHEAD, DEFAULT_IMAGE_SIZE
from vlm_bench.sim.framing import fits, view_xyaxes
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode, EpisodeObject
from vlm_bench.types.geometry import UAV_ARM_LENGTH, UAV_ROTOR_RADIUS

MIN_OBJECT_PX = 12
"""px at 448²: least size of a task object in its better third-person view."""
MIN_SMALL_PART_PX = 6
"""px at 448²: the same for a small part (:data:`SMALL_PART`)."""
SMALL_PART = 0.04
"""m: an object whose every dimension is under this is a small part (bolt, nut)."""
BOX_TO_SHAPE = 0.7
"""How much of its projected bounding box's shorter side an object is taken to fill."""
ESTIMATE_MARGIN = 1.15
"""The estimate must exceed the bound by this factor: a box misses an object's thin end and what
hides part of it (estimates of 12.0-13.4 px rendered 11 px: a banana, a cup, a cube behind a
basket)."""
UAV_HUB_RADIUS = UAV_ARM_LENGTH - UAV_ROTOR_RADIUS
"""m: the UAV's chassis, taken as a disc about its axis reaching the rotor discs (0.16 m, the
frame plate's half length)."""


def is_small_part(kind: str) -> bool:
    """Whether objects of ``kind`` are small parts, held to :data:`MIN_SMALL_PART_PX`."""
    return (
        max(object_kind(kind).size[:2]) < 2 * SMALL_PART
        and min(object_kind(kind).size) < SMALL_PART
    )


def min_pixels(kind: str) -> int:
    """Least size (px at 448²) an object of ``kind`` must have in its better view."""
    return MIN_SMALL_PART_PX if is_small_part(kind) else MIN_OBJECT_PX


def box_corners(obj: EpisodeObject) -> Vec:
    """The eight corners (m, world) of an object's bounding box."""
    sx, sy, sz = object_kind(obj.kind).size
    out = []
    for dx in (-sx / 2, sx / 2):
        for dy in (-sy / 2, sy / 2):
            rx, ry = rotate_xy(dx, dy, obj.yaw_deg)
            for z in (0.0, sz):
                out.append((obj.pos[0] + rx, obj.pos[1] + ry, obj.pos[2] + z))
    return np.array(out, dtype=np.float64)


def project(view: CameraView, points: Vec, size: int) -> Vec:
    """Pixel coordinates (u right, v up, from the image centre) of world points."""
    right, up = np.array(view_xyaxes(view.forward)).reshape(2, 3)
    fwd = view.forward / np.linalg.norm(view.forward)
    rel = points - view.pos
    focal = size / (2 * math.tan(math.radians(view.fovy / 2)))
    depth = rel @ fwd
    uv: Vec = focal * np.stack([rel @ right, rel @ up], axis=1) / depth[:, None]
    return uv


def projected_size(view: CameraView, obj: EpisodeObject, size: int) -> float:
    """Shorter side (px) of the bounding box of ``obj``'s box in ``view``, times
    :data:`BOX_TO_SHAPE`."""
    uv = project(view, box_corners(obj), size)
    span = uv.max(axis=0) - uv.min(axis=0)
    return round(BOX_TO_SHAPE * float(span.min()), 1)


def object_pixel_sizes(
    episode: Episode,
    size: int = DEFAULT_IMAGE_SIZE,
    views: dict[str, CameraView] | None = None,
) -> dict[str, dict[str, float]]:
    """Task object id → view → its size (px) by :func:`projected_size` (``views``: the
    episode's :func:`~vlm_bench.sim.cameras.third_person_views`, computed if not given)."""
    views = views if views is not None else third_person_views(episode)
    by_id = {o.id: o for o in episode.objects}
    return {
        oid: {name: projected_size(view, by_id[oid], size) for name, view in views.items()}
        for oid in task_objects(episode)
    }


def uav_covers(episode: Episode, view: CameraView, obj: EpisodeObject) -> bool:
    """Whether the UAV at its start hides ``obj`` from ``view``: the sight line to the centre
    of the object's top passes, at the UAV's altitude, through its chassis
    (:data:`UAV_HUB_RADIUS`) or one of its four rotor discs."""
    ux, uy, uz = episode.uav_start.pos
    top = np.array([*obj.pos[:2], obj.pos[2] + object_kind(obj.kind).size[2]])
    ray = top - view.pos
    if top[2] >= uz or ray[2] >= 0:  # at or above the UAV: nothing of the UAV is in front
        return False
    hit = view.pos + ray * (uz - view.pos[2]) / ray[2]
    bx, by = rotate_xy(float(hit[0] - ux), float(hit[1] - uy), -episode.uav_start.yaw_deg)
    if math.hypot(bx, by) <= UAV_HUB_RADIUS:
        return True
    rotor = UAV_ARM_LENGTH / math.sqrt(2)  # motor axes at +-45 and +-135 deg
    return any(
        math.hypot(bx - sx * rotor, by - sy * rotor) <= UAV_ROTOR_RADIUS
        for sx in (-1, 1)
        for sy in (-1, 1)
    )


def hidden_from_above(episode: Episode, views: dict[str, CameraView]) -> frozenset[str]:
    """Task objects the UAV covers (:func:`uav_covers`) in the overhead view of ``views``."""
    view = views.get(CAM_OVERHEAD)
    if view is None:
        return frozenset()
    by_id = {o.id: o for o in episode.objects}
    return frozenset(oid for oid in task_objects(episode) if uav_covers(episode, view, by_id[oid]))


def frame_problem(episode: Episode, views: dict[str, CameraView] | None = None) -> str | None:
    """Why a third-person view cuts off part of the work area (the UAV, a task object or a
    part the plan names), or None."""
    points, margins = framing_points(episode)
    views = views if views is not None else third_person_views(episode)
    for name, view in views.items():
        if not fits(view.pos, view.forward, view.fovy, points, margins):
            return f"the {name} view cuts off part of the work area"
    return None


def object_legibility(
    episode: Episode,
    sizes: dict[str, dict[str, float]],
    hidden: frozenset[str] = frozenset(),
) -> dict[str, float]:
    """Task object id -> the ratio of its size in its better view (``sizes``:
    :func:`object_pixel_sizes`) to :func:`min_pixels` times :data:`ESTIMATE_MARGIN`: legible
    when at least 1. An object in ``hidden`` (:func:`hidden_from_above`) has no overhead view."""
    kinds = {o.id: o.kind for o in episode.objects}
    return {
        oid: max(
            (px for view, px in by_view.items() if view != CAM_OVERHEAD or oid not in hidden),
            default=0.0,
        )
        / (min_pixels(kinds[oid]) * ESTIMATE_MARGIN)
        for oid, by_view in sizes.items()
    }


def legibility_score(
    episode: Episode,
    sizes: dict[str, dict[str, float]],
    hidden: frozenset[str] = frozenset(),
) -> float:
    """The least :func:`object_legibility` over task objects: legible when at least 1."""
    return min(object_legibility(episode, sizes, hidden).values(), default=float("inf"))


def view_legibility(episode: Episode, views: dict[str, CameraView]) -> float:
    """:func:`legibility_score` of ``episode`` shown with ``views``, the UAV covering what it
    covers from above."""
    sizes = object_pixel_sizes(episode, views=views)
    return legibility_score(episode, sizes, hidden_from_above(episode, views))
