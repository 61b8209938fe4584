"""Where and how the top-down gripper holds each kind of object.

The Panda hand opens 8 cm, so its fingers must close across an object's narrow side: a banana
or a chocolate box across its width, a box or a can across its 6 cm side. A mug is held around
its cup (the handle, along the mug's +x, stays beside the fingers); a bowl, 16 cm across, by its
rim, one finger inside and one outside the wall. The hand's x axis is its heading; the fingers
close along its y axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vlm_bench.executor.ik import top_down_rotation
from vlm_bench.types.world import ObjectKind

Vec = NDArray[np.float64]
MAX_ACROSS = 0.075  # m: widest span the open fingers close on with some clearance
RIM_INSET = 0.007  # m from a bowl's outer radius to the middle of its 1 cm wall
BELOW_TOP = 0.03  # m: fingers close this far below the top (at least 1.5 cm above the bottom)
RIM_BELOW_TOP = 0.02  # m: for rim grasps


@dataclass(frozen=True)
class GraspPoint:
    """A TCP position and the orientations the hand may take there."""

    point: Vec
    rotations: tuple[Vec, ...]


def _headings(base: float, n: int) -> tuple[Vec, ...]:
    """``n`` headings evenly spread from ``base`` (rad)."""
    return tuple(top_down_rotation(base + k * 2 * math.pi / n) for k in range(n))


def grasp_points(kind: ObjectKind, pos: Vec, yaw: float, lo: Vec, hi: Vec) -> list[GraspPoint]:
    """Candidate grasps of an object of ``kind`` whose body is at ``pos`` with heading ``yaw``
    (rad) and whose solid geoms span [lo, hi] now, best first."""
    sx, sy, _ = kind.size
    cy, sn = math.cos(yaw), math.sin(yaw)
    height = max(float(lo[2]) + 0.015, float(hi[2]) - BELOW_TOP)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, height])
    if kind.name == "bowl":
        radius = min(sx, sy) / 2 - RIM_INSET
        z = float(hi[2]) - RIM_BELOW_TOP
        out = []
        for k in range(8):
            a = yaw + k * math.pi / 4
            point = np.array([pos[0] + radius * math.cos(a), pos[1] + radius * math.sin(a), z])
            # Fingers close radially: the hand's y axis along the radius.
            out.append(GraspPoint(point, _headings(a + math.pi / 2, 2)))
        return out
    if kind.name == "mug":
        axis_x = -sx / 2 + sy / 2  # the cup's axis in the mug's frame (the handle fills +x)
        point = np.array([pos[0] + axis_x * cy, pos[1] + axis_x * sn, height])
        return [GraspPoint(point, _headings(yaw, 2))]  # fingers along the mug's y
    if max(sx, sy) <= MAX_ACROSS:
        return [GraspPoint(centre, _headings(yaw, 4))]
    # Close across the narrower side: the hand's x axis along the longer one.
    along = yaw if sx >= sy else yaw + math.pi / 2
    return [GraspPoint(centre, _headings(along, 2))]
