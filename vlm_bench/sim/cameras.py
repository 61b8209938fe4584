"""Fixed third-person cameras (``overhead``, ``side``) framed tightly on each episode's work area.

Each camera has a fixed viewing direction and is placed as close as it can be while it sees
every framing point grown by its margin (:func:`~vlm_bench.sim.framing.closest_fit`). The
overhead camera looks down, tilted a little towards +y, so image up is world +y and image right
world +x. The side camera looks at the area from above at :data:`SIDE_ELEVATION_DEG`, from the
azimuth nearest its preferred one at which the robot hides the fewest objects. A camera that
would stand outside the room gets a wider field of view, which brings it closer.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world_catalog import environment, object_kind
from vlm_bench.rules.cameras import (
    MAX_FOVY,
    OVERHEAD_FOVY,
    OVERHEAD_TILT_DEG,
    SIDE_ELEVATION_DEG,
    SIDE_FOVY,
)
from vlm_bench.sim.constants import (
    CAM_OVERHEAD,
    CAM_SIDE,
    UAV_HEADING_TAIL_X,
    UAV_HEADING_TIP_X,
    UAV_HEADING_Z,
)
from vlm_bench.sim.framing import (
    closest_fit,
    image_span,
    occluded,
    segment_hits_boxes,
)
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode, EpisodeObject

SIDE_AZIMUTH_STEP_DEG = 20.0  # candidate side azimuths: preferred one ± k steps
SIDE_MIN_ARROW = 0.045  # least length of the UAV's heading arrow in the side view (image sides)
FOVY_STEP = 5.0
WALL_CLEARANCE = 0.3  # least distance from a camera to the room's walls (m)
UAV_MARGIN = 0.6  # rotor tips reach 0.5 m from the UAV's centre, the heading arrow 0.52 m
OBJECT_MARGIN = 0.02  # added to half an object's box diagonal, so the view holds it whole (m)
PART_MARGIN = 0.1  # around a drawer handle or knob (m)
# The robot as spheres (offset below the UAV centre, radius; m): airframe, then the hanging arm.
ROBOT_SPHERES = ((0.0, 0.5), (0.35, 0.2), (0.65, 0.2))


def plan_references(episode: Episode) -> set[str]:
    """Ids of the objects and parts the GT plan's ARM steps name (as object or target)."""
    return {s.object for s in episode.arm_steps()} | {
        s.target for s in episode.arm_steps() if s.target
    }


def is_framed_object(obj: EpisodeObject, referenced: set[str]) -> bool:
    """Whether the views must show ``obj`` whole: the plan names it, or it is movable and not a
    support (furniture and supports are framed only when the plan names them or their part)."""
    kind = object_kind(obj.kind)
    return obj.id in referenced or (kind.movable and obj.role != "support")


def task_objects(episode: Episode) -> tuple[str, ...]:
    """Ids of the episode's task objects, in scene order: the framed objects
    (:func:`is_framed_object`) and the owners of the parts the plan names."""
    referenced = plan_references(episode)
    owners = {p.parent for p in episode.parts if p.id in referenced}
    return tuple(o.id for o in episode.objects if o.id in owners or is_framed_object(o, referenced))


def framing_points(episode: Episode) -> tuple[Vec, Vec]:
    """Points the third-person views must show, with a margin radius each (m).

    The UAV start first, then the plan's objects and parts and every movable object.
    """
    referenced = plan_references(episode)
    points, margins = [np.array(episode.uav_start.pos)], [UAV_MARGIN]
    for obj in episode.objects:
        kind = object_kind(obj.kind)
        if is_framed_object(obj, referenced):
            points.append(np.array(obj.pos) + np.array([0.0, 0.0, kind.size[2] / 2]))
            margins.append(0.5 * math.hypot(*kind.size) + OBJECT_MARGIN)
    for part in episode.parts:
        if part.id in referenced:
            points.append(np.array(part.handle))
            margins.append(PART_MARGIN)
    return np.stack(points), np.array(margins)


def place_camera(
    forward: Vec, fovy: float, points: Vec, margins: Vec, half_room: float
) -> tuple[Vec, float]:
    """The closest fit at ``fovy``, widened in steps up to :data:`MAX_FOVY` while the camera
    would stand outside the room (``|x|, |y| <= half_room``); clipped into it at the widest."""
    while True:
        pos = closest_fit(forward, fovy, points, margins)
        if np.abs(pos[:2]).max() <= half_room or fovy >= MAX_FOVY:
            break
        fovy = min(fovy + FOVY_STEP, MAX_FOVY)
    pos[:2] = np.clip(pos[:2], -half_room, half_room)
    return pos, fovy


def overhead_forward() -> Vec:
    """Viewing direction of the overhead camera: down, tilted towards +y."""
    tilt = math.radians(OVERHEAD_TILT_DEG)
    return np.array([0.0, math.sin(tilt), -math.cos(tilt)])


def side_forward(azimuth_deg: float, elevation_deg: float = SIDE_ELEVATION_DEG) -> Vec:
    """Viewing direction of a side camera standing at ``azimuth_deg`` from the area, looking
    down at ``elevation_deg``."""
    az, elev = math.radians(azimuth_deg), math.radians(elevation_deg)
    return -np.array([math.cos(az) * math.cos(elev), math.sin(az) * math.cos(elev), math.sin(elev)])


def preferred_side_azimuth(episode: Episode) -> float:
    """Articulated fixtures are seen from their front-side; else the area from its -y side."""
    for obj in episode.objects:
        if object_kind(obj.kind).parts:
            return obj.yaw_deg + 50.0
    return -90.0 + 20.0


def robot_spheres(episode: Episode) -> tuple[Vec, Vec]:
    """Centres and radii of spheres covering the UAV and its hanging arm at the start."""
    start = np.array(episode.uav_start.pos)
    centres = np.stack([start - np.array([0.0, 0.0, below]) for below, _ in ROBOT_SPHERES])
    return centres, np.array([radius for _, radius in ROBOT_SPHERES])


def heading_arrow_ends(episode: Episode) -> tuple[Vec, Vec]:
    """World positions of the tail and tip of the UAV's heading arrow at the start."""
    start, yaw = np.array(episode.uav_start.pos), math.radians(episode.uav_start.yaw_deg)
    front = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    lift = np.array([0.0, 0.0, UAV_HEADING_Z])
    tail, tip = UAV_HEADING_TAIL_X, UAV_HEADING_TIP_X
    return start + tail * front + lift, start + tip * front + lift


@dataclass(frozen=True)
class SightLines:
    """What may hide the framed objects from a camera: the points each framed object is sighted
    at (its centre and its top), the bounding boxes of all objects, and which box may hide which
    sight point (not the object's own box, its supports' down to the floor, nor those resting on
    it)."""

    sights: Vec  # (2K, 3)
    centres: Vec  # (M, 3)
    halves: Vec  # (M, 3)
    yaws: Vec  # (M,) deg
    may_hide: NDArray[np.bool_]  # (2K, M)


def object_boxes(objects: Sequence[EpisodeObject]) -> tuple[Vec, Vec, Vec]:
    """Centres (M, 3), half sizes (M, 3) and yaws (M, deg) of ``objects``' catalogue boxes,
    as :func:`~vlm_bench.sim.framing.segment_hits_boxes` takes them."""
    sizes = np.array([object_kind(o.kind).size for o in objects], dtype=np.float64).reshape(-1, 3)
    centres = np.array([o.pos for o in objects], dtype=np.float64).reshape(-1, 3)
    centres[:, 2] += sizes[:, 2] / 2
    return centres, sizes / 2, np.array([o.yaw_deg for o in objects], dtype=np.float64)


def sight_lines(episode: Episode) -> SightLines:
    """The :class:`SightLines` of the episode's framed objects (:func:`is_framed_object`)."""
    on = {o.id: o.on for o in episode.objects}

    def below(oid: str) -> set[str]:
        found: set[str] = set()
        while on.get(oid, "floor") != "floor" and on[oid] not in found:
            oid = on[oid]
            found.add(oid)
        return found

    centres, halves, yaws = object_boxes(episode.objects)
    referenced = plan_references(episode)
    sights, may_hide = [], []
    for k, obj in enumerate(episode.objects):
        if not is_framed_object(obj, referenced):
            continue
        row = [
            other.id != obj.id and other.id not in below(obj.id) and obj.id not in below(other.id)
            for other in episode.objects
        ]
        for lift in (0.0, halves[k, 2]):
            sights.append(centres[k] + np.array([0.0, 0.0, lift]))
            may_hide.append(row)
    n = len(episode.objects)
    return SightLines(
        sights=np.array(sights, dtype=np.float64).reshape(-1, 3),
        centres=centres,
        halves=halves,
        yaws=yaws,
        may_hide=np.array(may_hide, dtype=bool).reshape(-1, n),
    )


def hidden_by_objects(lines: SightLines, pos: Vec) -> float:
    """How many framed objects other objects may hide from a camera at ``pos``: each sight line
    of :func:`sight_lines` that passes through a box that may hide it counts half."""
    hits = segment_hits_boxes(pos, lines.sights, lines.centres, lines.halves, lines.yaws)
    return 0.5 * float((hits & lines.may_hide).sum())


def hidden_by_objects_each(lines: SightLines, pos: Vec) -> NDArray[np.bool_]:
    """For each framed object (scene order), whether another object may hide one of its sight
    lines from a camera at ``pos``."""
    hits = segment_hits_boxes(pos, lines.sights, lines.centres, lines.halves, lines.yaws)
    per_sight = np.any(hits & lines.may_hide, axis=1)
    blocked: NDArray[np.bool_] = np.any(per_sight.reshape(-1, 2), axis=1)
    return blocked


def side_camera(
    episode: Episode, points: Vec, margins: Vec, half_room: float
) -> tuple[Vec, Vec, float]:
    """Forward direction, position and fovy of the side camera.

    Of the azimuths preferred ± k steps round the circle, takes the one at which the robot
    (:func:`~vlm_bench.sim.framing.occluded`) and the other objects (:func:`hidden_by_objects`)
    may hide the least of the framed objects, then one that shows the heading arrow at least
    :data:`SIDE_MIN_ARROW` long (the arrow shortens when the UAV faces the camera or away from
    it), then the one nearest the preferred azimuth.
    """
    preferred = preferred_side_azimuth(episode)
    blockers, blocker_radii = robot_spheres(episode)
    lines = sight_lines(episode)
    tail, tip = heading_arrow_ends(episode)
    steps = round(180.0 / SIDE_AZIMUTH_STEP_DEG)
    offsets = [0, *(s * sign for s in range(1, steps) for sign in (1, -1)), steps]
    options = []
    for k in offsets:
        forward = side_forward(preferred + k * SIDE_AZIMUTH_STEP_DEG)
        pos, fovy = place_camera(forward, SIDE_FOVY, points, margins, half_room)
        hidden = float(occluded(pos, points[1:], margins[1:], blockers, blocker_radii).sum())
        hidden += hidden_by_objects(lines, pos)
        short = image_span(pos, forward, fovy, tail, tip) < SIDE_MIN_ARROW
        options.append(((hidden, short), forward, pos, fovy))
    _, forward, pos, fovy = min(options, key=lambda option: option[0])
    return forward, pos, fovy


@dataclass(frozen=True)
class CameraView:
    """A fixed camera: position (m, world), viewing direction and vertical field of view."""

    pos: Vec
    forward: Vec
    fovy: float


def third_person_views(episode: Episode) -> dict[str, CameraView]:
    """The ``overhead`` and ``side`` cameras framing the episode's work area."""
    points, margins = framing_points(episode)
    half_room = environment(episode.environment).room_half_size - WALL_CLEARANCE
    forward = overhead_forward()
    pos, fovy = place_camera(forward, OVERHEAD_FOVY, points, margins, half_room)
    views = {CAM_OVERHEAD: CameraView(pos, forward, fovy)}
    forward, pos, fovy = side_camera(episode, points, margins, half_room)
    views[CAM_SIDE] = CameraView(pos, forward, fovy)
    return views
