"""The UAV body frame: bearings, the eight direction sectors and where a straight move stops."""

from __future__ import annotations

import math
from collections.abc import Sequence

from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS, Direction

SECTOR_DEG = 45.0
"""Width of each of the eight horizontal direction sectors; ``front`` is centred on 0°."""


def wrap_deg(angle: float) -> float:
    """Wrap an angle to [-180, 180)."""
    return (angle + 180.0) % 360.0 - 180.0


def rotate_xy(x: float, y: float, yaw_deg: float) -> tuple[float, float]:
    """Rotate a planar vector counter-clockwise by ``yaw_deg``."""
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return c * x - s * y, s * x + c * y


def body_bearing_deg(uav_xy: Sequence[float], uav_yaw_deg: float, point: Sequence[float]) -> float:
    """Bearing of ``point`` from the UAV in its body frame (deg, CCW from its front)."""
    dx, dy = point[0] - uav_xy[0], point[1] - uav_xy[1]
    return wrap_deg(math.degrees(math.atan2(dy, dx)) - uav_yaw_deg)


def quantise_bearing(bearing_deg: float) -> tuple[Direction, float]:
    """Nearest of the eight sectors, and the margin (deg) to the closest sector boundary."""
    index = round(bearing_deg / SECTOR_DEG) % 8
    offset = abs(wrap_deg(bearing_deg - index * SECTOR_DEG))
    return HORIZONTAL_DIRECTIONS[index], SECTOR_DEG / 2 - offset


def move_stop(
    start_xy: Sequence[float],
    heading_deg: float,
    target_xy: Sequence[float],
    standoff: float,
    max_move: float,
) -> tuple[float, float]:
    """Where a straight flight along ``heading_deg`` stops for a target.

    The UAV stops where its horizontal distance to the target first equals ``standoff``; if the
    path never comes that close, at the closest approach; never beyond ``max_move``.
    """
    ux, uy = math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg))
    rx, ry = target_xy[0] - start_xy[0], target_xy[1] - start_xy[1]
    along = rx * ux + ry * uy
    perp2 = rx * rx + ry * ry - along * along
    if along <= 0:
        travel = 0.0
    elif perp2 >= standoff**2:
        travel = along
    else:
        travel = max(0.0, along - math.sqrt(standoff**2 - perp2))
    travel = min(travel, max_move)
    return start_xy[0] + ux * travel, start_xy[1] + uy * travel
