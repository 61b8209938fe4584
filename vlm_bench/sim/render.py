"""Offscreen camera snapshots and labelled contact sheets.

:class:`SnapshotRenderer` keeps one OpenGL context for its whole life and uploads a model's
textures to it once (an ``MjrContext``), then renders any camera at any size up to the model's
offscreen buffer from it. Creating a context costs ~300 ms on the CPU (llvmpipe) and uploading a
model ~75 ms, against a few ms per view, so a renderer should be reused across episodes.
"""

from __future__ import annotations

import os

# Headless by default; must happen before mujoco is first imported.
os.environ.setdefault("MUJOCO_GL", "egl")

import math
from collections.abc import Mapping, Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

from vlm_bench.closing import ClosesOnExit
from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.sim.gl_preload import before_first_gl_context
from vlm_bench.sim.labels import Font, ui_font

RGBImage = NDArray[np.uint8]
GeomIdImage = NDArray[np.int32]
DEFAULT_SHADOWS = True
_MAX_GEOM = 10_000


class SnapshotRenderer(ClosesOnExit):
    """Renders RGB snapshots from a model's named cameras, reusing one GL context.

    Use as a context manager or call :meth:`close`. A model's GPU resources are cached for the
    most recently rendered model (compared by identity); rendering another model replaces them.
    Textures edited in place on a cached model are not re-uploaded.
    """

    def __init__(self, shadows: bool = DEFAULT_SHADOWS) -> None:
        """Create a renderer; the GL context is made lazily on the first render.

        Args:
            shadows: Render shadow maps (key light casts shadows). Costs ~2-3× per view on CPU.
        """
        self.shadows = shadows
        self.context_builds = 0  # how many times a model was uploaded (diagnostics, tests)
        self._gl: mujoco.GLContext | None = None
        self._model: mujoco.MjModel | None = None
        self._mjr: mujoco.MjrContext | None = None
        self._scene: mujoco.MjvScene | None = None
        self._option = mujoco.MjvOption()
        self._buffers: dict[int, RGBImage] = {}

    def _posed_scene(
        self, model: mujoco.MjModel, data: mujoco.MjData, camera: str, size: int
    ) -> tuple[mujoco.MjvScene, mujoco.MjrContext]:
        """The bound scene, updated to ``data`` as seen from the fixed camera ``camera``."""
        scene, mjr = self._bind(model, size)
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FIXED
        cam.fixedcamid = _camera_id(model, camera)
        mujoco.mjv_updateScene(
            model, data, self._option, None, cam, mujoco.mjtCatBit.mjCAT_ALL, scene
        )
        return scene, mjr

    def render(
        self, model: mujoco.MjModel, data: mujoco.MjData, camera: str, size: int
    ) -> RGBImage:
        """Render one square view.

        Args:
            model: Compiled model; its offscreen buffer must be at least ``size`` square.
            data: State to render (``mj_forward`` must have run so poses are current).
            camera: Name of a camera in the model.
            size: Image side in pixels.

        Returns:
            A new ``(size, size, 3)`` uint8 RGB array, row 0 at the top.
        """
        scene, mjr = self._posed_scene(model, data, camera, size)
        scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.shadows
        rect = mujoco.MjrRect(0, 0, size, size)
        mujoco.mjr_render(rect, scene, mjr)
        buf = self._buffers.setdefault(size, np.empty((size, size, 3), dtype=np.uint8))
        mujoco.mjr_readPixels(buf, None, rect, mjr)
        return np.flipud(buf).copy()

    def render_segmentation(
        self, model: mujoco.MjModel, data: mujoco.MjData, camera: str, size: int
    ) -> GeomIdImage:
        """Render one square view as geom ids (which geom each pixel shows).

        Args:
            model: Compiled model; its offscreen buffer must be at least ``size`` square.
            data: State to render (``mj_forward`` must have run so poses are current).
            camera: Name of a camera in the model.
            size: Image side in pixels.

        Returns:
            A ``(size, size)`` int32 array of geom ids, -1 where no geom is seen (sky, or
            decoration that is not a geom); row 0 at the top. Transparent geoms count as opaque.
        """
        scene, mjr = self._posed_scene(model, data, camera, size)
        scene.flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = True
        scene.flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = True
        rect = mujoco.MjrRect(0, 0, size, size)
        try:
            mujoco.mjr_render(rect, scene, mjr)
        finally:
            scene.flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = False
            scene.flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = False
        buf = np.empty((size, size, 3), dtype=np.uint8)
        mujoco.mjr_readPixels(buf, None, rect, mjr)
        # IDCOLOR writes each scene geom's segid + 1 into the RGB bytes, little-endian; 0 is
        # background (as in mujoco.Renderer).
        seg = buf.astype(np.int32) @ np.array([1, 1 << 8, 1 << 16], dtype=np.int32)
        lookup = np.full(scene.ngeom + 1, -1, dtype=np.int32)
        for k in range(scene.ngeom):
            geom = scene.geoms[k]
            if geom.segid >= 0 and geom.objtype == mujoco.mjtObj.mjOBJ_GEOM:
                lookup[geom.segid + 1] = geom.objid
        seg[seg > scene.ngeom] = 0
        ids: GeomIdImage = np.flipud(lookup[seg]).copy()
        return ids

    def render_views(
        self, model: mujoco.MjModel, data: mujoco.MjData, cameras: Sequence[str], size: int
    ) -> dict[str, RGBImage]:
        """Render several cameras at one size; returns images keyed by camera name, in order."""
        return {name: self.render(model, data, name, size) for name in cameras}

    def close(self) -> None:
        """Free the GL resources; the renderer can be used again (it re-creates them)."""
        if self._gl is not None:
            if self._mjr is not None:
                self._gl.make_current()
                self._mjr.free()
            self._gl.free()
        self._gl, self._mjr, self._scene, self._model = None, None, None, None

    def _bind(self, model: mujoco.MjModel, size: int) -> tuple[mujoco.MjvScene, mujoco.MjrContext]:
        """Make the GL context current and (re)upload ``model`` if it is not the cached one."""
        width, height = model.vis.global_.offwidth, model.vis.global_.offheight
        if size < 1 or size > min(width, height):
            raise ConfigError(
                f"image size {size} must be in 1..{min(width, height)}: the model's offscreen "
                "buffer is smaller (raise spec.visual.global_.offwidth/offheight)"
            )
        if self._gl is None:
            before_first_gl_context()
            self._gl = _gl_context_class()(width, height)
        self._gl.make_current()
        if self._model is not model or self._mjr is None or self._scene is None:
            if self._mjr is not None:
                self._mjr.free()
            self._mjr = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_100)
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr)
            self._scene = mujoco.MjvScene(model, maxgeom=_MAX_GEOM)
            self._model = model
            self.context_builds += 1
        return self._scene, self._mjr


def _gl_context_class() -> type[mujoco.GLContext]:
    """The GL backend named by ``MUJOCO_GL`` now, even if mujoco was imported before it was set."""
    backend = os.environ.get("MUJOCO_GL", "").lower()
    if backend == "egl":
        from mujoco.egl import GLContext as EglContext

        return EglContext  # type: ignore[no-any-return]
    if backend == "osmesa":
        from mujoco.osmesa import GLContext as OsMesaContext

        return OsMesaContext  # type: ignore[no-any-return]
    return mujoco.GLContext  # type: ignore[no-any-return]


def _camera_id(model: mujoco.MjModel, camera: str) -> int:
    cam_id = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera))
    if cam_id < 0:
        names = [model.camera(i).name for i in range(model.ncam)]
        raise UnknownNameError("camera", camera, names)
    return cam_id


def contact_sheet(
    images: Mapping[str, RGBImage], title: str | None = None, columns: int = 2
) -> Image.Image:
    """Tile images into one sheet with a caption above each tile (and an optional title).

    Args:
        images: Caption (camera name, task id, ...) to ``(H, W, 3)`` uint8 image, in display
            order. Tiles may differ in size; each cell is as large as the largest tile.
        title: Text drawn across the top of the sheet, if given.
        columns: Tiles per row.

    Returns:
        An RGB ``PIL.Image``.
    """
    if not images:
        raise ConfigError("contact_sheet needs at least one image")
    if columns < 1:
        raise ConfigError(f"columns must be >= 1, got {columns}")
    tiles = [
        (caption, Image.fromarray(np.asarray(img, dtype=np.uint8)))
        for caption, img in images.items()
    ]
    tile_w = max(t.width for _, t in tiles)
    tile_h = max(t.height for _, t in tiles)
    cols = min(columns, len(tiles))
    rows = math.ceil(len(tiles) / cols)
    gap = max(4, tile_w // 64)
    font_px = max(12, min(28, tile_w // 14))
    caption_h = int(font_px * 1.5)
    title_h = int(font_px * 2.0) if title else 0
    sheet = Image.new(
        "RGB",
        (cols * (tile_w + gap) + gap, title_h + rows * (caption_h + tile_h + gap) + gap),
        (255, 255, 255),
    )
    draw = ImageDraw.Draw(sheet)
    if title:
        font = ui_font(int(font_px * 1.25))
        draw.text(
            (gap, title_h // 2),
            _fit(draw, title, font, sheet.width - 2 * gap),
            fill=(20, 20, 20),
            font=font,
            anchor="lm",
        )
    font = ui_font(font_px)
    for k, (caption, tile) in enumerate(tiles):
        x = gap + (k % cols) * (tile_w + gap)
        y = title_h + gap + (k // cols) * (caption_h + tile_h + gap)
        text = _fit(draw, caption, font, tile_w)
        draw.text(
            (x + tile_w // 2, y + caption_h // 2), text, fill=(20, 20, 20), font=font, anchor="mm"
        )
        sheet.paste(tile.convert("RGB"), (x + (tile_w - tile.width) // 2, y + caption_h))
    return sheet


def _fit(draw: ImageDraw.ImageDraw, text: str, font: Font, width: int) -> str:
    """Shorten ``text`` with an ellipsis until it fits ``width`` pixels."""
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "…", font=font) > width:
        text = text[:-1]
    return text + "…"
