"""The vertical edges along which a view shows a support's full height, as geometry.

A support's height is read from its top down to the floor. For a support on the floor (a
table, a stove) that is one of its box's four vertical edges: a top corner and the floor point
beneath it. A support resting on another (a plate or a block on a table) is read through the
one at the bottom of its stack (:func:`floor_support`): its own top, and the full height of the
floor support under it.

An edge's pixels are those of the *column* at its corner: the vertical square prism of side
:data:`COLUMN_SIDE` inside the box at that corner, from the floor to the top (a table's leg
stands inside it); its length is read from the top corner down to the floor point at the
middle of the column, where a table's leg stands. An edge can show its height only where one
of the two side faces meeting at it faces the camera (:meth:`HeightEdge.faces`: elsewhere the
support's own top stands in front of it, and its pixels would tell nothing of its height)
and the camera sees it from the side (:meth:`HeightEdge.pitch` at most
:data:`MAX_EDGE_PITCH`: from above, a leg shrinks to a stub beside the top). Both the rendered check
(:func:`vlm_bench.sim.view_checks.support_heights`) and the camera search
(:mod:`vlm_bench.sim.height_views`) read edges from here.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.rules import rotate_xy
from vlm_bench.sim.cameras import plan_references, task_objects
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode, EpisodeObject

COLUMN_SIDE = 0.1
"""m: side of the square column at a box corner whose pixels show its edge (a table's leg,
0.05 m thick, stands 0.04 m in from its top's edges: inside 0.09 m)."""
MAX_EDGE_PITCH = 60.0
"""deg: the steepest sight line (below the horizontal) to an edge's middle at which a view
shows its height: there it projects at least half as long (cos 60°) as an equally long width
across the view."""
MIN_EDGE_PX = 12
"""px at 448²: least projected length of an edge that shows a height (as large as the least
task object, :data:`~vlm_bench.sim.view_sizes.MIN_OBJECT_PX`)."""


@dataclass(frozen=True, eq=False)  # arrays: edges compare by identity
class HeightEdge:
    """One vertical edge of a support's box, from a top corner down to the floor (m, world)."""

    top: Vec  # (3,) the top corner
    floor: Vec  # (3,) the floor point beneath it
    normals: Vec  # (2, 3) outward normals of the two side faces meeting at the edge
    column: Vec  # (8, 3) corners of the column at the edge (module doc)
    axis: Vec  # (2, 3) the column's centre line: its floor point and its top point

    def faces(self, camera: Vec) -> bool:
        """Whether a side face meeting at the edge faces a camera at ``camera``."""
        return bool(((camera - self.top) @ self.normals.T > 0.0).any())

    def pitch(self, camera: Vec) -> float:
        """Angle (deg) below the horizontal of the sight line from ``camera`` to the middle of
        the column's centre line."""
        sight = self.axis.mean(axis=0) - camera
        return math.degrees(math.atan2(-float(sight[2]), math.hypot(sight[0], sight[1])))

    def seen_from(self, camera: Vec) -> bool:
        """Whether a camera at ``camera`` can see the edge's height: it faces a side face
        meeting at the edge and sees it at most :data:`MAX_EDGE_PITCH` from above."""
        return self.faces(camera) and self.pitch(camera) <= MAX_EDGE_PITCH


def height_supports(episode: Episode) -> tuple[str, ...]:
    """Ids of the supports whose height a plan's vertical moves depend on: every support under
    a task object (down to the floor) and every support the plan names (a place destination)."""
    by_id = {o.id: o for o in episode.objects}
    wanted: list[str] = []
    referenced = plan_references(episode)
    for oid in task_objects(episode):
        on = by_id[oid].on
        while on in by_id:
            if on not in wanted and object_kind(by_id[on].kind).support:
                wanted.append(on)
            on = by_id[on].on
    for oid in referenced:
        if oid in by_id and oid not in wanted and object_kind(by_id[oid].kind).support:
            wanted.append(oid)
    return tuple(o.id for o in episode.objects if o.id in wanted)


def floor_support(episode: Episode, support: str) -> EpisodeObject:
    """The object at the bottom of the stack under ``support`` (``support`` itself when it
    stands on the floor)."""
    by_id = {o.id: o for o in episode.objects}
    obj = by_id[support]
    while obj.on in by_id and obj.on != obj.id:
        obj = by_id[obj.on]
    return obj


def height_edges(obj: EpisodeObject) -> tuple[HeightEdge, ...]:
    """The four vertical edges of ``obj``'s box, its top at ``pos.z`` plus the kind's height
    and its floor at z = 0."""
    sx, sy, sz = object_kind(obj.kind).size
    top_z = obj.pos[2] + sz
    inset = min(COLUMN_SIDE, sx / 2, sy / 2)
    out = []
    for ex, ey in itertools.product((-1.0, 1.0), (-1.0, 1.0)):
        corners = []
        for dx, dy, z in itertools.product(
            (ex * sx / 2, ex * (sx / 2 - inset)), (ey * sy / 2, ey * (sy / 2 - inset)), (0, top_z)
        ):
            corners.append(_world(obj, dx, dy, z))
        mid_x, mid_y = ex * (sx / 2 - inset / 2), ey * (sy / 2 - inset / 2)
        normals = [(*rotate_xy(ex, 0.0, obj.yaw_deg), 0.0), (*rotate_xy(0.0, ey, obj.yaw_deg), 0.0)]
        out.append(
            HeightEdge(
                top=_world(obj, ex * sx / 2, ey * sy / 2, top_z),
                floor=_world(obj, ex * sx / 2, ey * sy / 2, 0.0),
                normals=np.array(normals, dtype=np.float64),
                column=np.array(corners, dtype=np.float64),
                axis=np.stack([_world(obj, mid_x, mid_y, 0.0), _world(obj, mid_x, mid_y, top_z)]),
            )
        )
    return tuple(out)


def _world(obj: EpisodeObject, dx: float, dy: float, z: float) -> Vec:
    """The world point at ``(dx, dy)`` in ``obj``'s frame, at height ``z``."""
    rx, ry = rotate_xy(dx, dy, obj.yaw_deg)
    return np.array([obj.pos[0] + rx, obj.pos[1] + ry, z], dtype=np.float64)
