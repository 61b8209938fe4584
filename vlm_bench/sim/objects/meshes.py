"""Vertex and face lists for the few shapes primitives cannot make (flat lists, metres)."""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.types.base import Vec3


def prism(
    sides: int,
    r_bottom: float,
    r_top: float,
    height: float,
    turn_deg: float = 0.0,
    origin: Vec3 = (0.0, 0.0, 0.0),
    along_x: bool = False,
) -> list[float]:
    """Vertices of a regular prism or frustum (its convex hull is the shape).

    Args:
        sides: Number of sides.
        r_bottom: Corner radius at the base.
        r_top: Corner radius at the top.
        height: Length along the axis (+z, or +x if ``along_x``), from ``origin``.
        turn_deg: Angle of the first corner about the axis.
        origin: Centre of the base.
        along_x: Run the axis along +x instead of +z (the polygon then lies in y-z).
    """
    ox, oy, oz = origin
    verts: list[float] = []
    for h, r in ((0.0, r_bottom), (height, r_top)):
        for k in range(sides):
            a = math.radians(turn_deg + 360.0 * k / sides)
            u, v = r * math.cos(a), r * math.sin(a)
            verts += [ox + h, oy + u, oz + v] if along_x else [ox + u, oy + v, oz + h]
    return verts


def hex_ring(
    corner_r: float, hole_r: float, h: float, turn_deg: float
) -> tuple[list[float], list[int]]:
    """Vertices and outward-wound triangles of a hexagonal prism with a round bore.

    The outline is sampled at 12 angles (corners and flat midpoints) matched by the bore.
    """
    n = 12
    verts: list[float] = []
    for z in (0.0, h):
        for k in range(n):
            a = math.radians(turn_deg + 30.0 * k)
            r_out = corner_r if k % 2 == 0 else corner_r * math.cos(math.radians(30.0))
            verts += [r_out * math.cos(a), r_out * math.sin(a), z]
        for k in range(n):
            a = math.radians(turn_deg + 30.0 * k)
            verts += [hole_r * math.cos(a), hole_r * math.sin(a), z]

    def v(top: int, inner: int, k: int) -> int:
        return top * 2 * n + inner * n + k % n

    faces: list[int] = []
    for k in range(n):
        quads = (
            (v(1, 0, k), v(1, 0, k + 1), v(1, 1, k + 1), v(1, 1, k)),  # top, facing +z
            (v(0, 0, k), v(0, 1, k), v(0, 1, k + 1), v(0, 0, k + 1)),  # bottom, facing -z
            (v(0, 0, k), v(0, 0, k + 1), v(1, 0, k + 1), v(1, 0, k)),  # outside
            (v(0, 1, k), v(1, 1, k), v(1, 1, k + 1), v(0, 1, k + 1)),  # bore, facing the axis
        )
        for a, b, c, d in quads:
            faces += [a, b, c, a, c, d]
    return verts, faces


def tube(rings: list[tuple[Vec3, float]], sides: int = 10) -> tuple[list[float], list[int]]:
    """Vertices and outward-wound triangles of a closed tube through ``rings``."""
    pts = [np.asarray(c, dtype=np.float64) for c, _ in rings]
    verts: list[float] = []
    for i, (centre, r) in enumerate(zip(pts, (r for _, r in rings), strict=True)):
        tangent = pts[min(i + 1, len(pts) - 1)] - pts[max(i - 1, 0)]
        tangent /= np.linalg.norm(tangent)
        normal = np.array([0.0, 0.0, 1.0]) - tangent[2] * tangent
        normal /= np.linalg.norm(normal)
        binormal = np.cross(tangent, normal)
        for k in range(sides):
            a = 2 * math.pi * k / sides
            verts += list(centre + r * (math.cos(a) * normal + math.sin(a) * binormal))
    n = len(rings)
    verts += [*pts[0], *pts[-1]]
    start, end = n * sides, n * sides + 1
    faces: list[int] = []
    for i in range(n - 1):
        for k in range(sides):
            a, b = i * sides + k, i * sides + (k + 1) % sides
            c, d = a + sides, b + sides
            faces += [a, b, c, b, d, c]
    for k in range(sides):
        faces += [start, (k + 1) % sides, k]
        base = (n - 1) * sides
        faces += [end, base + k, base + (k + 1) % sides]
    return verts, faces
