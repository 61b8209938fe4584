"""The third-person views an episode is shown with: its legible views, with the side camera
moved where they leave a height support's full height unseen.

A model judges how high a table stands only where a view shows it from its top down to the
floor (:mod:`vlm_bench.sim.support_edges`). The legible views (:func:`legible_views`: the
standard framing, or the close-up) frame the work area tightly and may cut a table's legs off.
Where, by geometry (:func:`~vlm_bench.sim.height_sight.heights_shown`), neither of them shows
a height support's top with the full height of the support at the bottom of its stack, the
side camera is chosen again from the close-up's candidates
(:func:`~vlm_bench.sim.legible_views.side_options`) at the close-up's elevations and the lower
:data:`~vlm_bench.rules.cameras.HEIGHT_SIDE_ELEVATIONS`, each direction with more candidates
that also frame a facing edge of such a floor support (each facing edge alone; for several
supports, the farthest facing edge of each together).

Legibility comes first: a candidate must keep each task object's legibility
(:func:`~vlm_bench.sim.legible_views.side_legibility`) up to :data:`KEPT_LEGIBILITY`, hide no
framed object that the legible side camera does not, keep every height support's top in frame,
stand at least level with the UAV's heading arrow (from below, the UAV hides it) and clear of
every object's box by :data:`CAMERA_CLEARANCE`. Of those, the one that shows the most
supports' heights is taken, then the one hiding the fewest objects, then the most legible; the
legible views stay where no candidate shows more.

Which views show a support's height is predicted by :mod:`vlm_bench.sim.height_sight`.
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from vlm_bench.catalog.world_catalog import environment, object_kind
from vlm_bench.rules import rotate_xy
from vlm_bench.rules.cameras import CLOSE_SIDE_ELEVATIONS, HEIGHT_SIDE_ELEVATIONS
from vlm_bench.sim.cameras import WALL_CLEARANCE, CameraView, heading_arrow_ends
from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_SIDE
from vlm_bench.sim.framing import view_xyaxes
from vlm_bench.sim.height_sight import EDGE_MARGIN, height_check, top_framed
from vlm_bench.sim.legible_views import (
    HEADROOM,
    Framing,
    hiding,
    legible_views,
    side_legibility,
    side_options,
)
from vlm_bench.sim.support_edges import floor_support, height_edges
from vlm_bench.sim.view_sizes import box_corners
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.base import Vec3
from vlm_bench.types.episode import CameraPose, Episode

if TYPE_CHECKING:  # the camera geometry imports no simulator: episodes are judged by it
    import mujoco

KEPT_LEGIBILITY = 1.05
"""A moved side camera keeps each task object's legibility ratio
(:func:`~vlm_bench.sim.view_sizes.object_legibility`) up to this: an object within 5 % of its
bound in the legible views, which were checked rendered, is shown no smaller (the estimate can
be a pixel over a render)."""
CAMERA_CLEARANCE = 0.1
"""m: least distance from a moved side camera to any object's box."""


def _edge_framing(episode: Episode, bases: list[str]) -> Framing:
    """For a side camera's viewing direction, the ends of the facing edges of ``bases``
    (floor supports) to frame with :data:`~vlm_bench.sim.height_sight.EDGE_MARGIN`: each facing
    edge alone, and, for several bases, one edge of each together (the edge farthest along the
    view, which moves the camera back least)."""
    by_id = {o.id: o for o in episode.objects}
    edges = {bid: height_edges(by_id[bid]) for bid in bases}

    def framing(forward: Vec) -> list[tuple[Vec, Vec]]:
        sets, farthest = [], []
        for bid in bases:
            facing = [e for e in edges[bid] if e.faces(e.top - 100.0 * forward)]
            ends = [np.stack([e.top, e.axis[0]]) for e in facing]
            sets += ends
            if ends:
                farthest.append(max(ends, key=lambda pair: float(pair[1] @ forward)))
        if len(farthest) > 1:
            sets.append(np.concatenate(farthest))
        return [(points, np.full(len(points), EDGE_MARGIN)) for points in sets]

    return framing


def _clear_of_objects(episode: Episode, pos: Vec) -> bool:
    """Whether a camera at ``pos`` stands outside every object's box by :data:`CAMERA_CLEARANCE`."""
    for obj in episode.objects:
        sx, sy, sz = object_kind(obj.kind).size
        dx, dy = rotate_xy(pos[0] - obj.pos[0], pos[1] - obj.pos[1], -obj.yaw_deg)
        inside = (
            abs(dx) < sx / 2 + CAMERA_CLEARANCE
            and abs(dy) < sy / 2 + CAMERA_CLEARANCE
            and obj.pos[2] - CAMERA_CLEARANCE < pos[2] < obj.pos[2] + sz + CAMERA_CLEARANCE
        )
        if inside:
            return False
    return True


def _above_arrow(episode: Episode, pos: Vec) -> bool:
    """Whether a camera at ``pos`` stands at least level with the UAV's heading arrow (on top
    of the UAV: from below, the UAV hides it)."""
    tail, tip = heading_arrow_ends(episode)
    return bool(pos[2] >= (tail[2] + tip[2]) / 2)


def full_height_views(episode: Episode, views: dict[str, CameraView]) -> dict[str, CameraView]:
    """``views`` (the legible views), or with the side camera the module doc chooses where they
    leave a height support's full height unseen."""
    heights_shown = height_check(episode)
    shown = heights_shown(views)
    if all(shown.values()):
        return views
    overhead, current = views[CAM_OVERHEAD], views[CAM_SIDE]
    missing = sorted({floor_support(episode, sid).id for sid, ok in shown.items() if not ok})
    half_room = environment(episode.environment).room_half_size - WALL_CLEARANCE
    legibility = side_legibility(episode, overhead)
    hidden_now = hiding(episode)(current.pos)
    floors = {k: min(r, KEPT_LEGIBILITY) for k, r in legibility(current, hidden_now).items()}
    by_id = {o.id: o for o in episode.objects}
    tops = [box_corners(by_id[sid]) for sid in shown]
    framing = _edge_framing(episode, missing)
    elevations = CLOSE_SIDE_ELEVATIONS + HEIGHT_SIDE_ELEVATIONS
    best: tuple[tuple[int, int, float, float], CameraView] | None = None
    for hidden, side in side_options(episode, half_room, framing, elevations):
        if not hidden <= hidden_now or not _above_arrow(episode, side.pos):
            continue
        ratios = legibility(side, hidden)
        if any(ratios[k] < floor for k, floor in floors.items()):
            continue
        if not _clear_of_objects(episode, side.pos) or not all(
            top_framed(overhead, top) or top_framed(side, top) for top in tops
        ):
            continue
        count = sum(heights_shown({CAM_OVERHEAD: overhead, CAM_SIDE: side}).values())
        score = min(ratios.values(), default=float("inf"))
        key = (count, -len(hidden), min(score, HEADROOM), score)
        if best is None or key > best[0]:
            best = (key, side)
    if best is None or best[0][0] <= sum(shown.values()):
        return views
    return {CAM_OVERHEAD: overhead, CAM_SIDE: best[1]}


def shown_views(episode: Episode) -> dict[str, CameraView]:
    """The views the episode is shown with (module doc): those the generator recorded in
    ``episode.cameras``, or else chosen here (the search takes ~1 s; executing a plan, which
    builds the scene but renders nothing, must not pay it)."""
    if episode.cameras:
        return {
            name: CameraView(np.array(cam.pos), np.array(cam.forward), cam.fovy)
            for name, cam in episode.cameras.items()
        }
    return _shown_views(episode.model_dump_json(exclude={"object_px", "cameras"}))


def camera_poses(views: dict[str, CameraView]) -> dict[str, CameraPose]:
    """``views`` as the episode records them (exactly: JSON keeps a float's every bit)."""
    return {
        name: CameraPose(pos=_vec3(view.pos), forward=_vec3(view.forward), fovy=float(view.fovy))
        for name, view in views.items()
    }


def _vec3(v: Vec) -> Vec3:
    return float(v[0]), float(v[1]), float(v[2])


@lru_cache(maxsize=256)  # a scene is built many times per episode; the search takes ~1 s
def _shown_views(episode_json: str) -> dict[str, CameraView]:
    episode = Episode.model_validate_json(episode_json)
    return full_height_views(episode, legible_views(episode))


def add_third_person_cameras(spec: mujoco.MjSpec, episode: Episode) -> None:
    """Add the ``overhead`` and ``side`` cameras of :func:`shown_views`."""
    for name, view in shown_views(episode).items():
        spec.worldbody.add_camera(
            name=name, pos=view.pos.tolist(), xyaxes=view_xyaxes(view.forward), fovy=view.fovy
        )
