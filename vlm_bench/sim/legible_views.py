"""The third-person views an episode is shown with: the standard framing, or a close-up where
the standard one leaves a task object under its least size.

The standard framing (:func:`~vlm_bench.sim.cameras.third_person_views`) is what the episode
generator judges layouts by, so the close-up never changes which layout an episode keeps. An
episode still short of the bound after the redraw (seed 0 keeps its canonical layout; a
two-table task spreads its objects over two or three metres) gets the close-up, the same
frame contents seen differently:

- the overhead camera at :data:`CLOSE_OVERHEAD_FOVY`, from higher up: nearly orthographic, so
  objects on tables lose less to the UAV above them;
- the side camera at the azimuth, elevation and field of view of :data:`CLOSE_SIDE_AZIMUTH_STEP`,
  :data:`CLOSE_SIDE_ELEVATIONS`, :data:`CLOSE_SIDE_FOVYS` that makes the least legible object
  largest: a wide view from close by makes the objects nearest to it large.

Each candidate still frames the whole work area (:func:`~vlm_bench.sim.framing.fits`) and shows
the heading arrow; of the candidates that make every object legible, the one where the robot
and the other objects may hide the fewest objects is taken, else the most legible.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from vlm_bench.catalog.world_catalog import environment
from vlm_bench.rules.cameras import (
    CLOSE_OVERHEAD_FOVY,
    CLOSE_SIDE_ELEVATIONS,
    CLOSE_SIDE_FOVYS,
    OVERHEAD_FOVY,
)
from vlm_bench.sim.cameras import (
    SIDE_MIN_ARROW,
    WALL_CLEARANCE,
    CameraView,
    framing_points,
    heading_arrow_ends,
    hidden_by_objects_each,
    is_framed_object,
    overhead_forward,
    place_camera,
    plan_references,
    preferred_side_azimuth,
    robot_spheres,
    side_forward,
    sight_lines,
    third_person_views,
)
from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_SIDE, DEFAULT_IMAGE_SIZE
from vlm_bench.sim.framing import fits, image_span, occluded, view_xyaxes
from vlm_bench.sim.view_sizes import (
    hidden_from_above,
    legibility_score,
    object_pixel_sizes,
    view_legibility,
)
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode

if TYPE_CHECKING:  # the camera geometry imports no simulator: episodes are judged by it
    import mujoco

CLOSE_SIDE_AZIMUTH_STEP = 20.0  # deg, round the whole circle from the preferred azimuth
HEADROOM = 1.25  # the geometric estimate may be this far above a rendered size

Sizes = dict[str, dict[str, float]]


def _sizes(episode: Episode, name: str, view: CameraView) -> dict[str, float]:
    """Task object id -> its size (px) in one view."""
    sizes = object_pixel_sizes(episode, DEFAULT_IMAGE_SIZE, {name: view})
    return {oid: by_view[name] for oid, by_view in sizes.items()}


def _joined(overhead: dict[str, float], side: dict[str, float]) -> Sizes:
    return {oid: {CAM_OVERHEAD: px, CAM_SIDE: side[oid]} for oid, px in overhead.items()}


def _hiding(episode: Episode) -> Callable[[Vec], set[str]]:
    """A function from a camera position to the ids of the framed objects the robot or
    another object may hide from it (:func:`~vlm_bench.sim.framing.occluded`,
    :func:`hidden_by_objects_each`)."""
    points, margins = framing_points(episode)
    blockers, blocker_radii = robot_spheres(episode)
    lines = sight_lines(episode)
    referenced = plan_references(episode)
    framed = [o.id for o in episode.objects if is_framed_object(o, referenced)]
    spheres, radii = points[1 : 1 + len(framed)], margins[1 : 1 + len(framed)]

    def may_hide(pos: Vec) -> set[str]:
        by_robot = occluded(pos, spheres, radii, blockers, blocker_radii)
        by_objects = hidden_by_objects_each(lines, pos)
        return {oid for k, oid in enumerate(framed) if by_robot[k] > 0 or by_objects[k]}

    return may_hide


def _side_options(episode: Episode, half_room: float) -> list[tuple[set[str], CameraView]]:
    """Close-up side cameras that frame the work area and show the heading arrow, each with
    the framed objects that may be hidden from it."""
    points, margins = framing_points(episode)
    tail, tip = heading_arrow_ends(episode)
    preferred = preferred_side_azimuth(episode)
    may_hide = _hiding(episode)
    out = []
    for azimuth in np.arange(0.0, 360.0, CLOSE_SIDE_AZIMUTH_STEP):
        for elevation in CLOSE_SIDE_ELEVATIONS:
            forward = side_forward(preferred + float(azimuth), elevation)
            for fovy in CLOSE_SIDE_FOVYS:
                pos, wide = place_camera(forward, fovy, points, margins, half_room)
                if not fits(pos, forward, wide, points, margins):
                    continue
                if image_span(pos, forward, wide, tail, tip) < SIDE_MIN_ARROW:
                    continue
                out.append((may_hide(pos), CameraView(pos, forward, wide)))
    return out


def close_up_views(episode: Episode) -> dict[str, CameraView] | None:
    """The close-up framing of the module docstring, or None if no candidate frames the work
    area. An object that may be hidden from a side camera counts there as 0 px."""
    points, margins = framing_points(episode)
    half_room = environment(episode.environment).room_half_size - WALL_CLEARANCE
    forward = overhead_forward()
    pos, fovy = place_camera(forward, CLOSE_OVERHEAD_FOVY, points, margins, half_room)
    if not fits(pos, forward, fovy, points, margins):
        pos, fovy = place_camera(forward, OVERHEAD_FOVY, points, margins, half_room)
    overhead = CameraView(pos, forward, fovy)
    from_above = _sizes(episode, CAM_OVERHEAD, overhead)
    covered = hidden_from_above(episode, {CAM_OVERHEAD: overhead})
    best: tuple[tuple[float, int, float], CameraView] | None = None
    for hidden, side in _side_options(episode, half_room):
        beside = {
            k: 0.0 if k in hidden else px for k, px in _sizes(episode, CAM_SIDE, side).items()
        }
        score = legibility_score(episode, _joined(from_above, beside), covered)
        key = (min(score, HEADROOM), -len(hidden), score)
        if best is None or key > best[0]:
            best = (key, side)
    return None if best is None else {CAM_OVERHEAD: overhead, CAM_SIDE: best[1]}


def legible_views(episode: Episode) -> dict[str, CameraView]:
    """The views the episode is shown with: the standard framing, or the close-up where that
    leaves a task object under its least size and the close-up shows it larger."""
    views = third_person_views(episode)
    if view_legibility(episode, views) >= 1.0:
        return views
    return _shown_views(episode.model_dump_json(exclude={"object_px"}))


@lru_cache(maxsize=256)  # a scene is built many times per episode; the search takes ~0.3 s
def _shown_views(episode_json: str) -> dict[str, CameraView]:
    episode = Episode.model_validate_json(episode_json)
    views = third_person_views(episode)
    score = view_legibility(episode, views)
    close = close_up_views(episode)
    if close is None:
        return views
    closer = view_legibility(episode, close)
    return close if closer > score else views


def add_third_person_cameras(spec: mujoco.MjSpec, episode: Episode) -> None:
    """Add the ``overhead`` and ``side`` cameras of :func:`legible_views`."""
    for name, view in legible_views(episode).items():
        spec.worldbody.add_camera(
            name=name, pos=view.pos.tolist(), xyaxes=view_xyaxes(view.forward), fovy=view.fovy
        )
