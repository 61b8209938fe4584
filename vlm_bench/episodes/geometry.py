"""Plane geometry for layouts and GT derivation: bearings, sectors, rectangles, UAV stops."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS, Direction

SECTOR_DEG = 45.0


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
    """Where a straight flight along ``heading_deg`` stops for a target (SPEC §7).

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


def rect_corners(center: Sequence[float], size_xy: Sequence[float], yaw_deg: float) -> np.ndarray:
    """Corners (4, 2) of a yawed rectangle."""
    hx, hy = size_xy[0] / 2, size_xy[1] / 2
    pts = [rotate_xy(sx * hx, sy * hy, yaw_deg) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    corners: np.ndarray = np.asarray(pts) + np.asarray(center[:2])
    return corners


def rects_overlap(a: np.ndarray, b: np.ndarray, gap: float = 0.0) -> bool:
    """Separating-axis test of two convex quads (corner arrays), inflated by ``gap``."""
    for poly in (a, b):
        for i in range(4):
            edge = poly[(i + 1) % 4] - poly[i]
            axis = np.array([-edge[1], edge[0]]) / (np.linalg.norm(edge) + 1e-12)
            pa, pb = a @ axis, b @ axis
            if pa.max() + gap <= pb.min() or pb.max() + gap <= pa.min():
                return False
    return True


def point_rect_distance(point: Sequence[float], corners: np.ndarray) -> float:
    """Horizontal distance from a point to a (convex) rectangle; 0 inside."""
    p = np.asarray(point[:2], dtype=float)
    center = corners.mean(axis=0)
    ex = corners[0] - corners[1]
    ey = corners[1] - corners[2]
    lx, ly = np.linalg.norm(ex), np.linalg.norm(ey)
    d = p - center
    qx = abs(float(d @ ex) / float(lx)) - float(lx) / 2
    qy = abs(float(d @ ey) / float(ly)) - float(ly) / 2
    return float(math.hypot(max(qx, 0.0), max(qy, 0.0)))


def segment_rect_distance(a: Sequence[float], b: Sequence[float], corners: np.ndarray) -> float:
    """Smallest distance between a segment and a rectangle (sampled every 5 cm)."""
    length = math.dist(a[:2], b[:2])
    n = max(2, int(length / 0.05) + 1)
    return min(
        point_rect_distance((a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t), corners)
        for t in np.linspace(0.0, 1.0, n)
    )
