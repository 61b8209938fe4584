"""The legible third-person views: the standard framing, or a close-up where the standard one
leaves a task object under its least size. The views an episode is shown with are these, with
the side camera moved where they cut a table's legs off (:mod:`vlm_bench.sim.height_views`,
which reuses the close-up's side candidates).

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
from vlm_bench.sim.framing import fits, image_span, occluded
from vlm_bench.sim.view_sizes import (
    hidden_from_above,
    object_legibility,
    object_pixel_sizes,
    view_legibility,
)
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode

CLOSE_SIDE_AZIMUTH_STEP = 20.0  # deg, round the whole circle from the preferred azimuth
HEADROOM = 1.25  # the geometric estimate may be this far above a rendered size

Sizes = dict[str, dict[str, float]]


def _sizes(episode: Episode, name: str, view: CameraView) -> dict[str, float]:
    """Task object id -> its size (px) in one view."""
    sizes = object_pixel_sizes(episode, DEFAULT_IMAGE_SIZE, {name: view})
    return {oid: by_view[name] for oid, by_view in sizes.items()}


def _joined(overhead: dict[str, float], side: dict[str, float]) -> Sizes:
    return {oid: {CAM_OVERHEAD: px, CAM_SIDE: side[oid]} for oid, px in overhead.items()}


def hiding(episode: Episode) -> Callable[[Vec], set[str]]:
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


Framing = Callable[[Vec], list[tuple[Vec, Vec]]]
"""A function from a side camera's viewing direction to the sets of points, each with its
margins (m), that a candidate looking that way frames besides the work area."""


def side_directions(
    episode: Episode, elevations: tuple[float, ...] = CLOSE_SIDE_ELEVATIONS
) -> list[Vec]:
    """The close-up side cameras' viewing directions: every :data:`CLOSE_SIDE_AZIMUTH_STEP`
    round the circle from the preferred azimuth, at each of ``elevations`` (deg)."""
    preferred = preferred_side_azimuth(episode)
    return [
        side_forward(preferred + float(azimuth), elevation)
        for azimuth in np.arange(0.0, 360.0, CLOSE_SIDE_AZIMUTH_STEP)
        for elevation in elevations
    ]


def side_options(
    episode: Episode,
    half_room: float,
    extra: Framing | None = None,
    elevations: tuple[float, ...] = CLOSE_SIDE_ELEVATIONS,
) -> list[tuple[set[str], CameraView]]:
    """Close-up side cameras (:func:`side_directions` at ``elevations``, each of
    :data:`~vlm_bench.rules.cameras.CLOSE_SIDE_FOVYS`) that frame the work area and show the
    heading arrow, each with the framed objects that may be hidden from it. ``extra``: more
    candidates per direction, each also framing one set of points it gives."""
    points, margins = framing_points(episode)
    tail, tip = heading_arrow_ends(episode)
    may_hide = hiding(episode)
    out = []
    for forward in side_directions(episode, elevations):
        framings = [(points, margins)]
        framings += [
            (np.concatenate([points, more]), np.concatenate([margins, grown]))
            for more, grown in (extra(forward) if extra is not None else [])
        ]
        for fovy in CLOSE_SIDE_FOVYS:
            for framed, framed_margins in framings:
                pos, wide = place_camera(forward, fovy, framed, framed_margins, half_room)
                if not fits(pos, forward, wide, framed, framed_margins):
                    continue
                if image_span(pos, forward, wide, tail, tip) < SIDE_MIN_ARROW:
                    continue
                out.append((may_hide(pos), CameraView(pos, forward, wide)))
    return out


def side_legibility(
    episode: Episode, overhead: CameraView
) -> Callable[[CameraView, set[str]], dict[str, float]]:
    """A function from a side camera and the objects ``hidden`` from it (they count as 0 px
    there) to each task object's :func:`~vlm_bench.sim.view_sizes.object_legibility` with it
    and ``overhead``."""
    from_above = _sizes(episode, CAM_OVERHEAD, overhead)
    covered = hidden_from_above(episode, {CAM_OVERHEAD: overhead})

    def ratios(side: CameraView, hidden: set[str]) -> dict[str, float]:
        sizes = _sizes(episode, CAM_SIDE, side)
        beside = {k: 0.0 if k in hidden else px for k, px in sizes.items()}
        return object_legibility(episode, _joined(from_above, beside), covered)

    return ratios


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
    legibility = side_legibility(episode, overhead)
    best: tuple[tuple[float, int, float], CameraView] | None = None
    for hidden, side in side_options(episode, half_room):
        score = min(legibility(side, hidden).values(), default=float("inf"))
        key = (min(score, HEADROOM), -len(hidden), score)
        if best is None or key > best[0]:
            best = (key, side)
    return None if best is None else {CAM_OVERHEAD: overhead, CAM_SIDE: best[1]}


def legible_views(episode: Episode) -> dict[str, CameraView]:
    """The legible views: the standard framing, or the close-up where that leaves a task object
    under its least size and the close-up shows it larger."""
    views = third_person_views(episode)
    if view_legibility(episode, views) >= 1.0:
        return views
    return _legible_views(episode.model_dump_json(exclude={"object_px", "cameras"}))


@lru_cache(maxsize=256)  # a scene is built many times per episode; the search takes ~0.3 s
def _legible_views(episode_json: str) -> dict[str, CameraView]:
    episode = Episode.model_validate_json(episode_json)
    views = third_person_views(episode)
    score = view_legibility(episode, views)
    close = close_up_views(episode)
    if close is None:
        return views
    closer = view_legibility(episode, close)
    return close if closer > score else views
