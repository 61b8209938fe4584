"""Where and how the top-down gripper holds each kind of object.

The Panda hand opens 8 cm, so its fingers must close across an object's narrow side: a banana
or a chocolate box across its width, a box or a can across its 6 cm side, a 7 cm bolt across
its shaft (end to end it slips out), a hex nut across two flats. A bowl, 16 cm across, and a
mug, whose 7.2 cm cup leaves the open fingers 4 mm each side, are held by the rim, one finger
inside and one outside the wall, closing radially; a mug's rim away from its handle (+x). A
teddy bear is held by its head, across the ears; a cleanser bottle by its cap, the nozzle
beside the pads. The hand's x axis is its heading; the fingers close along its y axis.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from vlm_bench.executor.motion.ik import top_down_rotation
from vlm_bench.sim.objects.industrial import NUT_FLAT_DEG
from vlm_bench.types.base import FloatArray
from vlm_bench.types.world import ObjectKind

MAX_ACROSS = 0.075  # m: widest span the open fingers close on with some clearance
SQUARE = 0.6  # narrow/long side ratio above which an object is closed on from either side
RIM_INSET = 0.007  # m from a bowl's outer radius to the middle of its 1 cm wall
BELOW_TOP = 0.03  # m: fingers close this far below the top (at least 1.5 cm above the bottom)
RIM_BELOW_TOP = 0.02  # m: for rim grasps
CAP_BELOW_TOP = 0.014  # m: a cleanser is held by its cap's middle
TEDDY_HEAD = (-0.008, 0.125)  # m: the head's centre (x, height) in a 0.17 m bear's frame
MUG_RIM_INSET = 0.0065  # m from the foot's radius to the middle of the cup's wall
MUG_RIM_ANGLES = (180.0, 135.0, 225.0, 90.0, 270.0)  # deg from the handle, best first


@dataclass(frozen=True)
class GraspPoint:
    """A TCP position and the orientations the hand may take there; ``centre_across``: the
    fingers close on whatever cross-section of the object lies between them, so the point is
    to be centred on it (a curved banana's middle is not its bounding box's)."""

    point: FloatArray
    rotations: tuple[FloatArray, ...]
    centre_across: bool = False


def _headings(base: float, n: int) -> tuple[FloatArray, ...]:
    """``n`` headings evenly spread from ``base`` (rad)."""
    return tuple(top_down_rotation(base + k * 2 * math.pi / n) for k in range(n))


def _rim(
    axis: FloatArray, radius: float, top: float, yaw: float, angles_deg: Iterable[float]
) -> list[GraspPoint]:
    """Rim grasps of a round vessel about the vertical through ``axis`` (x, y), at
    ``angles_deg`` from the object's +x: fingers astride the wall, closing radially."""
    out = []
    for deg in angles_deg:
        a = yaw + math.radians(deg)
        point = np.array([axis[0] + radius * math.cos(a), axis[1] + radius * math.sin(a), 0.0])
        point[2] = top - RIM_BELOW_TOP
        out.append(GraspPoint(point, _headings(a + math.pi / 2, 2)))  # the hand's y radial
    return out


def grasp_points(
    kind: ObjectKind,
    pos: FloatArray,
    yaw: float,
    lo: FloatArray,
    hi: FloatArray,
    com: FloatArray | None = None,
) -> list[GraspPoint]:
    """Candidate grasps of an object of ``kind`` whose body is at ``pos`` with heading ``yaw``
    (rad) and whose solid geoms span [lo, hi] now, best first. A long object is held level
    with its centre of mass ``com`` along its length (a bolt's heavy head would swing it
    round the fingers)."""
    sx, sy, sz = kind.size
    cy, sn = math.cos(yaw), math.sin(yaw)
    height = max(float(lo[2]) + 0.015, float(hi[2]) - BELOW_TOP)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, height])
    if kind.name == "bowl":
        radius = min(sx, sy) / 2 - RIM_INSET
        return _rim(pos[:2], radius, float(hi[2]), yaw, (k * 45.0 for k in range(8)))
    if kind.name == "mug":
        axis_x = -sx / 2 + sy / 2  # the cup's axis in the mug's frame (the handle fills +x)
        axis = pos[:2] + axis_x * np.array([cy, sn])
        return _rim(axis, min(sx, sy) / 2 - MUG_RIM_INSET, float(hi[2]), yaw, MUG_RIM_ANGLES)
    if kind.name == "teddy_bear":
        # By the head, across its ears, at the head's equator: squeezed above it, a sphere
        # pops out of the fingers (the bear's layout scales with its height, see sim.objects).
        k = sz / 0.17
        head = np.array([pos[0] + TEDDY_HEAD[0] * k * cy, pos[1] + TEDDY_HEAD[0] * k * sn, 0.0])
        head[2] = float(lo[2]) + TEDDY_HEAD[1] * k
        return [GraspPoint(head, _headings(yaw, 2))]
    if kind.name == "cleanser":
        # By the cap (2.8 cm tall for the pads' 2.6 cm): the palm would meet it lower down.
        # A pad never rests on a feature narrower than itself: the pads close on the cap's
        # round sides with the nozzle along the hand's x, beside them. A pad on the nozzle's
        # 8 mm end holds a grip unstable about the vertical that a turn of the hand spins out.
        cap = np.array([pos[0], pos[1], float(hi[2]) - CAP_BELOW_TOP])
        return [GraspPoint(cap, _headings(yaw, 2))]
    if kind.name == "nut":
        # Across two flats (any of three pairs, either way round): closing on two corners,
        # the pads push the nut round, and the six headings leave more ways past a wall.
        flats = yaw + math.radians(NUT_FLAT_DEG) - math.pi / 2  # the hand's y on a flat normal
        return [GraspPoint(centre, _headings(flats, 6))]
    if max(sx, sy) <= MAX_ACROSS and min(sx, sy) >= SQUARE * max(sx, sy):
        return [GraspPoint(centre, _headings(yaw, 4))]
    # Close across the narrower side: the hand's x axis along the longer one.
    along = yaw if sx >= sy else yaw + math.pi / 2
    if com is not None:
        axis = np.array([math.cos(along), math.sin(along)])
        centre[:2] += axis * float(np.dot(np.asarray(com)[:2] - centre[:2], axis))
    return [GraspPoint(centre, _headings(along, 2), centre_across=True)]
