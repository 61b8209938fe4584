"""Plane geometry for layouts and GT checks: rectangles and clearances (the body-frame rules
themselves live in :mod:`vlm_bench.rules.frame`)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from vlm_bench.rules.frame import rotate_xy


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
