"""Whether a third-person view shows a support's full height, predicted from geometry.

An edge is predicted shown in a view when the camera sees it from the side
(:meth:`~vlm_bench.sim.support_edges.HeightEdge.seen_from`), its top corner and the floor
point at the middle of its column lie inside the frame by :data:`EDGE_MARGIN`, at least
:data:`HEIGHT_HEADROOM` times :data:`~vlm_bench.sim.support_edges.MIN_EDGE_PX` rows apart,
and neither another object's box nor the robot lies on the sight lines to its column's centre
line at :data:`EDGE_SIGHTS`, nor the support's own top on those up to
:data:`UNDER_TOP_SHARE` of its height. The rendered check is
:func:`vlm_bench.sim.view_checks.support_heights`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.sim.cameras import CameraView, object_boxes, robot_spheres
from vlm_bench.sim.constants import DEFAULT_IMAGE_SIZE
from vlm_bench.sim.framing import fits, segment_hits_boxes
from vlm_bench.sim.support_edges import (
    MIN_EDGE_PX,
    HeightEdge,
    floor_support,
    height_edges,
    height_supports,
)
from vlm_bench.sim.view_sizes import box_corners, project
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode

EDGE_MARGIN = 0.05
"""m: least room round an edge's two ends inside a frame that shows it."""
HEIGHT_HEADROOM = 1.25
"""The predicted length of an edge must exceed its bound by this factor."""
EDGE_SIGHTS = (0.1, 0.3, 0.5, 0.7, 0.9)
"""Shares of an edge's height at which its column's centre line is sighted: nothing else may
stand on these sight lines."""
UNDER_TOP_SHARE = 0.7
"""The support's own top may not stand on the sight lines up to this share of its height
(just under the top, its overhang may hide a leg that its side and apron stand in for)."""
TOP_SLAB = 0.01
"""m: thickness of the slab that stands for a support's own top on the sight lines."""


class _Sight:
    """What may stand between a camera and a floor support's legs: the other objects' boxes,
    the robot's spheres, and the support's own top (as a slab :data:`TOP_SLAB` thick)."""

    def __init__(self, episode: Episode, base: str) -> None:
        self.others = object_boxes([o for o in episode.objects if o.id != base])
        own = [o for o in episode.objects if o.id == base]
        centres, halves, yaws = object_boxes(own)
        centres[:, 2] = [o.pos[2] + object_kind(o.kind).size[2] - TOP_SLAB / 2 for o in own]
        halves[:, 2] = TOP_SLAB / 2
        self.top = centres, halves, yaws
        self.spheres, self.radii = robot_spheres(episode)

    def clear(self, pos: Vec, points: Vec) -> bool:
        """Whether no other object's box nor the robot lies on the segments from ``pos`` to
        ``points``."""
        if len(self.others[0]) and segment_hits_boxes(pos, points, *self.others).any():
            return False
        ray = points - pos  # (N, 3); the spheres' nearest points on each segment
        t = np.clip(((self.spheres - pos) @ ray.T) / (ray * ray).sum(axis=1), 0.0, 1.0)  # (S, N)
        nearest = pos + t[..., None] * ray[None]
        dist = np.linalg.norm(nearest - self.spheres[:, None, :], axis=-1)
        return bool((dist > self.radii[:, None]).all())

    def under_top(self, pos: Vec, points: Vec) -> bool:
        """Whether the support's own top stays off the segments from ``pos`` to ``points``."""
        return not bool(segment_hits_boxes(pos, points, *self.top).any())


def edge_shown(view: CameraView, edge: HeightEdge, sight: _Sight) -> bool:
    """Whether ``view`` shows ``edge`` whole, as predicted (module doc)."""
    ends = np.stack([edge.top, edge.axis[0]])
    if not edge.seen_from(view.pos) or not fits(
        view.pos, view.forward, view.fovy, ends, np.full(2, EDGE_MARGIN)
    ):
        return False
    rows = project(view, ends, DEFAULT_IMAGE_SIZE)[:, 1]
    if abs(float(rows[0] - rows[1])) < HEIGHT_HEADROOM * MIN_EDGE_PX:
        return False
    low, high = edge.axis
    shares = np.array(EDGE_SIGHTS)
    sights = low + shares[:, None] * (high - low)
    return sight.clear(view.pos, sights) and sight.under_top(
        view.pos, sights[shares <= UNDER_TOP_SHARE]
    )


def top_framed(view: CameraView, corners: Vec) -> bool:
    """Whether a corner of a box's top face (``corners``: its eight corners) lies in frame."""
    top = corners[1::2]
    return any(fits(view.pos, view.forward, view.fovy, p[None], np.zeros(1)) for p in top)


def heights_shown(episode: Episode, views: dict[str, CameraView]) -> dict[str, bool]:
    """For each height support (:func:`~vlm_bench.sim.support_edges.height_supports`), whether
    one of ``views`` frames its top and shows an edge of its floor support whole (module
    doc)."""
    return height_check(episode)(views)


def height_check(episode: Episode) -> Callable[[dict[str, CameraView]], dict[str, bool]]:
    """:func:`heights_shown` for ``episode``, its supports' edges and sight lines made once (a
    camera search asks it of many views)."""
    by_id = {o.id: o for o in episode.objects}
    targets = []
    for sid in height_supports(episode):
        base = floor_support(episode, sid)
        targets.append((sid, box_corners(by_id[sid]), height_edges(base), _Sight(episode, base.id)))

    def shown(views: dict[str, CameraView]) -> dict[str, bool]:
        return {
            sid: any(
                top_framed(view, corners) and any(edge_shown(view, e, sight) for e in edges)
                for view in views.values()
            )
            for sid, corners, edges, sight in targets
        }

    return shown
