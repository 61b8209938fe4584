"""Set-of-marks labels: project world points into a camera image and draw small tags there.

Pixel coordinates are continuous ``(u, v)`` with the origin at the image's top-left corner, u to
the right and v down; pixel ``[row, col]`` covers ``[col, col + 1) × [row, row + 1)``, so its
centre is at ``(col + 0.5, row + 0.5)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cache

import mujoco
import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw, ImageFont

from vlm_bench.errors import UnknownNameError

RGBImage = NDArray[np.uint8]
Box = tuple[float, float, float, float]
"""A pixel box ``(u0, v0, u1, v1)``."""
Font = ImageFont.FreeTypeFont | ImageFont.ImageFont

_TAG_FILL = (255, 255, 255)
_TAG_TEXT = (15, 15, 25)
_TAG_EDGE = (30, 30, 40)
_DOT = (255, 40, 40)


@cache
def ui_font(size: int) -> Font:
    """Pillow's built-in font at ``size`` px (no font files or downloads needed)."""
    return ImageFont.load_default(size=size)


def project_points(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera: str,
    points: NDArray[np.floating],
    width: int,
    height: int,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Project world points into a camera's image (pinhole model, as MuJoCo renders it).

    MuJoCo cameras look along their local -z with y up; ``model.cam_fovy`` is the vertical field
    of view (deg), or the vertical extent (m) for orthographic cameras. Uses the camera pose in
    ``data`` (``cam_xpos``, ``cam_xmat``), so ``mj_forward`` must have run.

    Args:
        model: Compiled model.
        data: State whose camera poses are current.
        camera: Camera name.
        points: World points, shape ``(N, 3)``.
        width: Image width in pixels.
        height: Image height in pixels.

    Returns:
        ``(uv, visible)``: pixel coordinates ``(N, 2)`` and a mask of points in front of the
        camera and inside the image. Occlusion is not checked.
    """
    cam_id = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera))
    if cam_id < 0:
        raise UnknownNameError("camera", camera, [model.camera(i).name for i in range(model.ncam)])
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    rot = data.cam_xmat[cam_id].reshape(3, 3)  # columns: camera x, y, z axes in world
    local = (pts - data.cam_xpos[cam_id]) @ rot  # world -> camera frame
    depth = -local[:, 2]
    fovy = float(model.cam_fovy[cam_id])
    if model.cam_projection[cam_id] == mujoco.mjtProjection.mjPROJ_ORTHOGRAPHIC:
        focal = height / fovy
        scale = np.full_like(depth, focal)
    else:
        focal = 0.5 * height / math.tan(math.radians(fovy) / 2.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = focal / depth
    uv = np.stack([width / 2.0 + local[:, 0] * scale, height / 2.0 - local[:, 1] * scale], axis=1)
    inside = (uv[:, 0] >= 0) & (uv[:, 0] < width) & (uv[:, 1] >= 0) & (uv[:, 1] < height)
    visible = (depth > 0) & inside & np.isfinite(uv).all(axis=1)
    return uv, visible


def tag_layout(
    image: tuple[int, int],
    labels: Sequence[tuple[str, tuple[float, float]]],
    avoid: Sequence[Box] = (),
) -> list[tuple[str, tuple[float, float], Box]]:
    """Where :func:`draw_labels` puts each tag: ``(text, point, box)`` for the labels whose
    point lies inside an ``image`` of ``(width, height)`` px.

    Each tag goes to the spot round its point that covers the least of ``avoid`` (the pixel
    boxes of the task objects), then of earlier tags and marked points, then the nearest one
    (up-right first) that stays inside the image.
    """
    w, h = image
    font_px, pad, offset, dot = _metrics(h)
    font = ui_font(font_px)
    inside = [(t, (u, v)) for t, (u, v) in labels if 0 <= u < w and 0 <= v < h]
    marks = [(u - 2 * dot, v - 2 * dot, u + 2 * dot, v + 2 * dot) for _, (u, v) in inside]
    placed: list[Box] = []
    out = []
    for text, point in inside:
        left, top, right, bottom = font.getbbox(text)
        size = (right - left + 2 * pad, bottom - top + 2 * pad)
        box = _place(point, size, offset, (w, h), list(avoid), placed + marks)
        placed.append(box)
        out.append((text, point, box))
    return out


def _metrics(height: int) -> tuple[int, int, int, int]:
    """Font size, tag padding, tag offset and dot radius (px) for an image ``height`` px high."""
    font_px = max(10, min(22, height // 28))
    return font_px, max(2, font_px // 5), max(6, font_px // 2), max(2, font_px // 6)


def draw_labels(
    image: RGBImage,
    labels: Sequence[tuple[str, tuple[float, float]]],
    avoid: Sequence[Box] = (),
) -> RGBImage:
    """Draw set-of-marks tags: a dot at each point and a white tag with dark text beside it.

    Tags are placed by :func:`tag_layout` (off the ``avoid`` boxes, off each other and the
    marked points, inside the image); a thin leader joins tag and dot. Points outside the image
    are skipped.

    Args:
        image: ``(H, W, 3)`` uint8 RGB image (not modified).
        labels: ``(text, (u, v))`` pairs in pixel coordinates (see module docstring).
        avoid: Pixel boxes ``(u0, v0, u1, v1)`` no tag should cover (the task objects).

    Returns:
        A new image with the tags drawn.
    """
    out = Image.fromarray(np.asarray(image, dtype=np.uint8)).convert("RGB")
    draw = ImageDraw.Draw(out)
    font_px, pad, _, dot = _metrics(out.size[1])
    font = ui_font(font_px)
    layout = tag_layout(out.size, labels, avoid)
    for text, (u, v), box in layout:
        left, top, _, _ = font.getbbox(text)
        anchor = (min(max(u, box[0]), box[2]), min(max(v, box[1]), box[3]))
        draw.line([(u, v), anchor], fill=_TAG_EDGE, width=1)
        draw.rectangle(box, fill=_TAG_FILL, outline=_TAG_EDGE, width=1)
        draw.text((box[0] + pad - left, box[1] + pad - top), text, fill=_TAG_TEXT, font=font)
    for _, (u, v), _ in layout:  # dots last, so no tag hides a point
        draw.ellipse((u - dot, v - dot, u + dot, v + dot), fill=_DOT, outline=_TAG_EDGE)
    return np.asarray(out, dtype=np.uint8).copy()


# Tag directions from the point, in order of preference: up-right, up-left, down-right, ...
_DIRECTIONS = ((1, -1), (-1, -1), (1, 1), (-1, 1), (0, -1), (0, 1), (1, 0), (-1, 0))
_RINGS = (1.0, 2.5, 4.5, 7.0, 10.0)


def _place(
    point: tuple[float, float], size: tuple[float, float], offset: float,
    image: tuple[int, int], avoid: list[Box], obstacles: list[Box],
) -> Box:  # fmt: skip
    """The tag box with the least overlap with ``avoid``, then with ``obstacles``, then
    nearest, then least clamped."""
    (u, v), (bw, bh), (w, h) = point, size, image
    best: tuple[float, float, int, float, int] | None = None
    best_box: Box = (0.0, 0.0, bw, bh)
    for ring_index, ring in enumerate(_RINGS):
        for k, (dx, dy) in enumerate(_DIRECTIONS):
            x = u + dx * offset * ring - (bw if dx < 0 else bw / 2 if dx == 0 else 0.0)
            y = v + dy * offset * ring - (bh if dy < 0 else bh / 2 if dy == 0 else 0.0)
            x0 = min(max(x, 0.0), max(w - 1 - bw, 0.0))
            y0 = min(max(y, 0.0), max(h - 1 - bh, 0.0))
            box = (x0, y0, x0 + bw, y0 + bh)
            cost = (
                sum(_overlap(box, o) for o in avoid),
                sum(_overlap(box, o) for o in obstacles),
                ring_index,
                abs(x0 - x) + abs(y0 - y),
                k,
            )
            if best is None or cost < best:
                best, best_box = cost, box
    return best_box


def _overlap(a: Box, b: Box) -> float:
    """Area shared by two boxes (0 when apart)."""
    return max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
