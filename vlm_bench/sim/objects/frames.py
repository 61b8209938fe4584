"""Rotations for placing geoms: quaternions (w, x, y, z) from axes, angles and segments."""

from __future__ import annotations

import math

from vlm_bench.types.base import Vec3

Quat = tuple[float, float, float, float]
IDENTITY: Quat = (1.0, 0.0, 0.0, 0.0)


def axis_angle(axis: Vec3, deg: float) -> Quat:
    """Unit quaternion (w, x, y, z) of a rotation by ``deg`` degrees about ``axis``."""
    norm = math.sqrt(sum(a * a for a in axis))
    half = math.radians(deg) / 2.0
    s = math.sin(half) / norm
    return (math.cos(half), axis[0] * s, axis[1] * s, axis[2] * s)


def quat_mul(a: Quat, b: Quat) -> Quat:
    """Hamilton product ``a * b`` (apply ``b`` first, then ``a``)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def yaw(deg: float) -> Quat:
    """Rotation about +z by ``deg`` degrees."""
    return axis_angle((0.0, 0.0, 1.0), deg)


def segment(a: Vec3, b: Vec3) -> tuple[Vec3, Quat, float]:
    """Centre, orientation (local z along a→b) and half-length of the segment a→b."""
    d = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    length = math.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
    centre = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2)
    z = (d[0] / length, d[1] / length, d[2] / length)
    # Shortest-arc rotation from +z to z (antiparallel case: half turn about x).
    if z[2] < -1.0 + 1e-9:
        return centre, (0.0, 1.0, 0.0, 0.0), length / 2
    w = 1.0 + z[2]
    q = (w, -z[1], z[0], 0.0)
    n = math.sqrt(sum(c * c for c in q))
    return centre, (q[0] / n, q[1] / n, q[2] / n, q[3] / n), length / 2
