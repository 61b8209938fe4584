"""The third-person cameras' fixed angles: the one source for the cameras and the prompt.

:mod:`vlm_bench.sim.cameras`, :mod:`vlm_bench.sim.legible_views` and
:mod:`vlm_bench.sim.height_views` place the ``overhead`` and ``side`` cameras with these
angles; the system prompt describes the cameras with the same numbers (:func:`camera_numbers`),
so a model can correct for their perspective.
"""

from __future__ import annotations

from functools import cache

from pydantic import Field

from vlm_bench.types.base import Frozen

OVERHEAD_FOVY = 30.0
"""deg: the overhead camera's vertical field of view."""
OVERHEAD_TILT_DEG = 11.3
"""deg: the overhead camera's tilt from straight down towards image up, so heights read."""
SIDE_FOVY = 40.0
"""deg: the side camera's vertical field of view."""
SIDE_ELEVATION_DEG = 28.0
"""deg: how far below the horizontal the side camera looks."""
MAX_FOVY = 75.0
"""deg: the widest field of view used to bring a camera inside a small room."""
CLOSE_OVERHEAD_FOVY = 15.0
"""deg: the close-up overhead's field of view (from higher up: nearly orthographic)."""
CLOSE_SIDE_ELEVATIONS = (28.0, 40.0, 55.0)
"""deg: the close-up side camera's candidate elevations."""
CLOSE_SIDE_FOVYS = (40.0, 55.0, 70.0, 85.0)
"""deg: the close-up side camera's candidate fields of view."""
HEIGHT_SIDE_ELEVATIONS = (15.0, 20.0)
"""deg: lower elevations the side camera may also take to show a table down to the floor
(a view from lower down frames a table's legs at less cost to the objects' sizes)."""


class CameraNumbers(Frozen):
    """What the prompt says about the third-person cameras."""

    overhead_pitch: float = Field(description="Overhead: degrees below the horizontal.")
    overhead_tilt: float = Field(description="Overhead: degrees from straight down.")
    overhead_fovy: float = Field(description="Overhead: vertical field of view (deg).")
    close_overhead_fovy: float = Field(description="Close-up overhead's field of view (deg).")
    max_fovy: float = Field(description="Widest field of view in a small room (deg).")
    side_pitch: float = Field(description="Side: degrees below the horizontal.")
    side_fovy: float = Field(description="Side: vertical field of view (deg).")
    close_side_pitches: tuple[float, ...] = Field(description="Close-up side's elevations (deg).")
    close_side_fovys: tuple[float, ...] = Field(description="Close-up side's fields of view.")
    height_side_pitches: tuple[float, ...] = Field(
        description="Lower elevations (deg) the side may take to show a table to the floor."
    )


@cache
def camera_numbers() -> CameraNumbers:
    """The cameras' angles as the prompt states them."""
    return CameraNumbers(
        overhead_pitch=round(90.0 - OVERHEAD_TILT_DEG, 1),
        overhead_tilt=OVERHEAD_TILT_DEG,
        overhead_fovy=OVERHEAD_FOVY,
        close_overhead_fovy=CLOSE_OVERHEAD_FOVY,
        max_fovy=MAX_FOVY,
        side_pitch=SIDE_ELEVATION_DEG,
        side_fovy=SIDE_FOVY,
        close_side_pitches=CLOSE_SIDE_ELEVATIONS,
        close_side_fovys=CLOSE_SIDE_FOVYS,
        height_side_pitches=HEIGHT_SIDE_ELEVATIONS,
    )
