"""Video of a plan execution: an observer that renders one camera every few control steps and
streams the frames to an MP4 (imageio-ffmpeg, the ``video`` extra) or a GIF (Pillow).

Frames are rendered with :class:`~vlm_bench.sim.render.SnapshotRenderer` every ``stride``
control steps (20 Hz), so the video plays in real time at ``20 / stride`` frames per second.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import TracebackType
from typing import Any, Protocol

import mujoco
import numpy as np
from numpy.typing import NDArray
from PIL import Image

from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import CAM_SIDE, CONTROL_DT
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import Scene

CONTROL_HZ = round(1.0 / CONTROL_DT)
"""Control steps per simulated second (the recorder's clock)."""
VIDEO_FORMATS = (".mp4", ".gif")
"""File suffixes the recorder writes."""

Frame = NDArray[np.uint8]


class FrameSink(Protocol):
    """Where frames go: appended one by one, finished by :meth:`close`."""

    def append(self, frame: Frame) -> None:
        """Add one ``(H, W, 3)`` uint8 RGB frame."""

    def close(self) -> None:
        """Finish the file."""


class GifSink:
    """Collects palette frames (a third of the RGB memory) and writes the GIF on close."""

    def __init__(self, path: Path, fps: float) -> None:
        self.path = path
        self.duration_ms = round(1000.0 / fps)
        self._frames: list[Image.Image] = []

    def append(self, frame: Frame) -> None:
        """Quantise ``frame`` to 256 colours and keep it."""
        self._frames.append(Image.fromarray(frame).quantize(256))

    def close(self) -> None:
        """Write the looping GIF (nothing if no frame was added)."""
        if self._frames:
            first, *rest = self._frames
            first.save(
                self.path, save_all=True, append_images=rest, duration=self.duration_ms, loop=0
            )
        self._frames = []


class Mp4Sink:
    """Streams frames to ffmpeg (H.264, yuv420p) through imageio."""

    def __init__(self, path: Path, fps: float) -> None:
        if importlib.util.find_spec("imageio") is None or (
            importlib.util.find_spec("imageio_ffmpeg") is None
        ):
            raise MissingExtraError("imageio-ffmpeg (for MP4 videos; GIF needs nothing)", "video")
        import imageio.v2 as imageio

        self._writer: Any = imageio.get_writer(
            str(path),
            format="FFMPEG",
            mode="I",
            fps=fps,
            codec="libx264",
            pixelformat="yuv420p",
            macro_block_size=1,
            quality=7,
        )

    def append(self, frame: Frame) -> None:
        """Encode one frame."""
        self._writer.append_data(frame)

    def close(self) -> None:
        """Flush and close the file."""
        self._writer.close()


def open_sink(path: Path, fps: float, size: int) -> FrameSink:
    """The sink for ``path``'s format (by suffix).

    Raises:
        ConfigError: An unknown suffix, or an odd size for MP4 (H.264 needs even sides).
        MissingExtraError: MP4 without imageio-ffmpeg.
    """
    suffix = path.suffix.lower()
    if suffix == ".gif":
        return GifSink(path, fps)
    if suffix == ".mp4":
        if size % 2:
            raise ConfigError(f"MP4 videos need an even frame size, got {size}")
        return Mp4Sink(path, fps)
    raise ConfigError(
        f"unknown video format {path.suffix or path.name!r}; valid: " + ", ".join(VIDEO_FORMATS)
    )


def frame_stride(fps: float) -> int:
    """Control steps between frames for about ``fps`` frames per second (at least 1).

    Raises:
        ConfigError: ``fps`` not in (0, 20].
    """
    if not 0 < fps <= CONTROL_HZ:
        raise ConfigError(f"video fps must be in (0, {CONTROL_HZ}], got {fps:g}")
    return max(1, round(CONTROL_HZ / fps))


class VideoRecorder:
    """Observer for :func:`~vlm_bench.executor.execute_plan` that records one camera.

    Call :meth:`start` with the scene before executing (it records the first frame and checks
    the camera name), pass the recorder in ``observers``, then :meth:`close` (or use ``with``).

    Args:
        path: Output file, ``.mp4`` or ``.gif``.
        camera: Camera name in the scene (``uav``, ``wrist``, ``overhead``, ``side``, ...).
        size: Frame side in pixels (square frames).
        fps: Wanted frames per second; the recorder keeps every ``round(20 / fps)``-th control
            step, so the actual rate is :attr:`fps`.
        renderer: A renderer to reuse (its GL context); default: one owned by the recorder.
        shadows: Shadows in the recorder's own renderer (2–3× the cost per frame on a CPU).

    Raises:
        ConfigError: Bad format, size or fps. MissingExtraError: MP4 without the extra.
    """

    def __init__(
        self,
        path: Path | str,
        camera: str = CAM_SIDE,
        size: int = 480,
        fps: float = 10.0,
        renderer: SnapshotRenderer | None = None,
        shadows: bool = True,
    ) -> None:
        if size < 16:
            raise ConfigError(f"video size must be at least 16 pixels, got {size}")
        self.path = Path(path)
        self.camera = camera
        self.size = size
        self.stride = frame_stride(fps)
        self.fps = CONTROL_HZ / self.stride
        """Frames per second of the written video (simulated time plays in real time)."""
        self.frames = 0
        """Frames written so far."""
        self._sink = open_sink(self.path, self.fps, size)
        self._renderer = renderer or SnapshotRenderer(shadows=shadows)
        self._owns_renderer = renderer is None
        self._steps = 0
        self._closed = False

    def start(self, scene: Scene) -> None:
        """Record the start state (raises UnknownNameError for an unknown camera)."""
        self.capture(scene.model, scene.data)

    def capture(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Render the camera now and append the frame."""
        self._sink.append(self._renderer.render(model, data, self.camera, self.size))
        self.frames += 1

    def __call__(self, loop: SimLoop) -> None:
        """Called after every control step: keep every :attr:`stride`-th."""
        self._steps += 1
        if self._steps % self.stride == 0:
            self.capture(loop.model, loop.data)

    def close(self) -> Path:
        """Finish the file and free the renderer (if owned); idempotent. Returns the path."""
        if not self._closed:
            self._closed = True
            self._sink.close()
            if self._owns_renderer:
                self._renderer.close()
        return self.path

    def __enter__(self) -> VideoRecorder:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
