"""Camera framing geometry: fit spheres into a square view frustum, and test occlusion.

A camera here has a fixed viewing direction and a vertical field of view ``fovy`` (deg) on a
square image; its axes follow :func:`view_xyaxes` (image up as close to world +z as possible).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import NDArray

from vlm_bench.types.base import FloatArray as Vec


def _cross(a: Vec, b: Vec) -> Vec:
    """Cross product of two 3-vectors (``np.cross`` is slow on single vectors)."""
    out: Vec = np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )
    return out


def view_xyaxes(forward: Vec) -> list[float]:
    """MuJoCo ``xyaxes`` (image right, image up) of a camera looking along ``forward``."""
    right, up, _ = _axes(forward)
    return [*right.tolist(), *up.tolist()]


def _axes(forward: Vec) -> tuple[Vec, Vec, Vec]:
    """Image right, image up and the unit viewing direction of a camera looking along
    ``forward`` (read-only arrays, cached per direction)."""
    return _axes_of(np.asarray(forward, dtype=np.float64).tobytes())


@functools.lru_cache(maxsize=4096)
def _axes_of(forward_bytes: bytes) -> tuple[Vec, Vec, Vec]:
    """:func:`_axes` of a direction given as its float64 bytes: a camera search asks for the
    same few candidate directions hundreds of times."""
    forward = np.frombuffer(forward_bytes, dtype=np.float64)
    forward = forward / np.linalg.norm(forward)
    up_hint = np.array([0.0, 0.0, 1.0])
    if abs(float(forward @ up_hint)) > 0.999:  # looking straight down: pick +y as image up
        up_hint = np.array([0.0, 1.0, 0.0])
    right = _cross(forward, up_hint)
    right /= np.linalg.norm(right)
    up = _cross(right, forward)
    for axis in (right, up, forward):
        axis.flags.writeable = False
    return right, up, forward


def fits(pos: Vec, forward: Vec, fovy: float, points: Vec, margins: Vec) -> bool:
    """True when every sphere (point, margin) lies inside the square view frustum of a camera
    at ``pos`` looking along ``forward`` (up to 1 µm)."""
    right, up, fwd = _axes(forward)
    tan = math.tan(math.radians(fovy / 2))
    rel = points - pos
    depth = rel @ fwd
    grown = margins * math.hypot(1.0, tan)  # a plane's distance -> offset along the image axis
    return all(
        bool((np.abs(rel @ axis) + grown <= tan * depth + 1e-6).all()) for axis in (right, up)
    )


def closest_fit(forward: Vec, fovy: float, points: Vec, margins: Vec) -> Vec:
    """The closest camera position, looking along ``forward``, that sees every sphere whole.

    A sphere (p, m) lies inside the square frustum (half-angle ``a``, ``t = tan a``) of a camera
    at ``c`` when ``|e·(p-c)| + m·sqrt(1+t²) <= t·f·(p-c)`` for both image axes ``e``, ``f``
    being the viewing direction: linear in ``c``. For one axis, ``e·c`` has a feasible interval
    while ``f·c <= (min(e·p + t·f·p - m') - max(e·p - t·f·p + m')) / 2t``; the camera goes as
    far forward as both axes allow and sits at the middle of each interval.
    """
    right, up, fwd = _axes(forward)
    tan = math.tan(math.radians(fovy / 2))
    grown = margins * math.hypot(1.0, tan)
    depth = points @ fwd
    bounds = []
    for axis in (right, up):
        across = points @ axis
        bounds.append(
            (
                float(np.max(across - tan * depth + grown)),
                float(np.min(across + tan * depth - grown)),
            )
        )
    ahead = min((upper - lower) / (2 * tan) for lower, upper in bounds)
    (r_lo, r_hi), (u_lo, u_hi) = bounds
    pos: Vec = (r_lo + r_hi) / 2 * right + (u_lo + u_hi) / 2 * up + ahead * fwd
    return pos


def image_span(pos: Vec, forward: Vec, fovy: float, a: Vec, b: Vec) -> float:
    """Distance between the images of points ``a`` and ``b`` (in front of the camera at
    ``pos``), as a fraction of the square image's side."""
    right, up, fwd = _axes(forward)
    tan = math.tan(math.radians(fovy / 2))
    ends = np.stack([a, b]) - pos
    image = np.stack([ends @ right, ends @ up], axis=1) / (ends @ fwd)[:, None] / (2 * tan)
    return float(np.linalg.norm(image[1] - image[0]))


def occluded(pos: Vec, points: Vec, radii: Vec, blockers: Vec, blocker_radii: Vec) -> Vec:
    """For each sphere (point, radius), how many blocker spheres may hide part of it from a
    camera at ``pos``: blockers whose centre is nearer and whose angular disc overlaps its own."""
    to_p, to_b = points - pos, blockers - pos
    dist_p, dist_b = np.linalg.norm(to_p, axis=1), np.linalg.norm(to_b, axis=1)
    cos = (to_p @ to_b.T) / np.outer(dist_p, dist_b)
    angle = np.arccos(np.clip(cos, -1.0, 1.0))
    reach = (
        np.arcsin(np.clip(blocker_radii / dist_b, 0.0, 1.0))[None, :]
        + np.arcsin(np.clip(radii / dist_p, 0.0, 1.0))[:, None]
    )
    nearer = dist_b[None, :] < dist_p[:, None]
    counts: Vec = ((angle < reach) & nearer).sum(axis=1).astype(np.float64)
    return counts


def segment_hits_boxes(
    start: Vec, ends: Vec, centres: Vec, halves: Vec, yaws_deg: Vec
) -> NDArray[np.bool_]:
    """Whether the segment from ``start`` to each point of ``ends`` (N, 3) passes through each
    box (M centres, M half sizes, each turned by its yaw about z), the end itself excluded:
    an (N, M) array."""
    yaw = np.radians(np.asarray(yaws_deg, dtype=np.float64))
    cos, sin = np.cos(yaw), np.sin(yaw)

    def to_boxes(vectors: Vec) -> Vec:  # (K, M, 3) world vectors -> each box's frame
        x, y = vectors[..., 0], vectors[..., 1]
        out: Vec = np.stack([cos * x + sin * y, -sin * x + cos * y, vectors[..., 2]], axis=-1)
        return out

    origin = to_boxes((start - centres)[None])  # (1, M, 3)
    delta = to_boxes(np.broadcast_to((ends - start)[:, None, :], (len(ends), len(centres), 3)))
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (-halves - origin) / delta, (halves - origin) / delta
    inside = np.abs(origin) <= halves  # a segment parallel to a slab: inside it or never
    parallel = delta == 0
    lo = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2))
    hi = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2))
    enter, leave = lo.max(axis=-1), hi.min(axis=-1)
    hits: NDArray[np.bool_] = (enter <= leave) & (leave >= 0.0) & (enter < 1.0 - 1e-9)
    return hits
