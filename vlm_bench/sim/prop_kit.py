"""The kit decorative props are built with: names, the keep-out rule, colours, the local frame
(:class:`PropPlacer`), wall fixtures (windows, doors, frames). The props of each environment are in
:mod:`~vlm_bench.sim.props_indoor` and :mod:`~vlm_bench.sim.props_outdoor`; :mod:`.props` picks
them.

Props are visual-only geoms in the world body named ``prop/<what>/<part>``; every one stays farther
than :data:`KEEP_OUT_RADIUS` horizontally from the origin (against the walls indoors), so they never
block cameras looking at the work area. Composite props are laid out in a local frame
(:class:`PropPlacer`); indoors that frame sits on a wall: x along the wall, y into the room, z up.
"""

from __future__ import annotations

import math

import mujoco

from vlm_bench.catalog.world_catalog import color
from vlm_bench.sim.materials import solid_material
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.world import EnvironmentSpec

PROP_PREFIX = "prop/"
KEEP_OUT_RADIUS = 3.8
Colour = str | RGBA

GLASS: RGBA = (0.62, 0.78, 0.92, 1.0)
LEAF: RGBA = (0.14, 0.42, 0.16, 1.0)
BRICK: RGBA = (0.62, 0.28, 0.2, 1.0)
SCREEN: RGBA = (0.03, 0.03, 0.05, 1.0)
CARDBOARD: RGBA = (0.72, 0.55, 0.35, 1.0)


class PropPlacer:
    """Adds visual-only primitives in a local frame (origin + yaw) under one name prefix."""

    def __init__(
        self, spec: mujoco.MjSpec, prefix: str, origin: tuple[float, float], yaw_deg: float = 0.0
    ) -> None:
        """Create a placer.

        Args:
            spec: Scene under construction.
            prefix: Geom name prefix, e.g. ``prop/fridge/``.
            origin: World (x, y) of the local frame's origin (on the floor).
            yaw_deg: Rotation of the local frame about z (deg).
        """
        self.spec, self.prefix, self.origin = spec, prefix, origin
        self.yaw = math.radians(yaw_deg)

    def _world(self, pos: Vec3) -> list[float]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        x, y, z = pos
        return [self.origin[0] + c * x - s * y, self.origin[1] + s * x + c * y, z]

    def _quat(self, axis: str) -> list[float]:
        yaw = [math.cos(self.yaw / 2), 0.0, 0.0, math.sin(self.yaw / 2)]
        if axis == "z":
            return yaw
        # Turn the geom's z axis onto local x (about y) or local y (about x), then yaw.
        w, z = yaw[0], yaw[3]
        h = math.sqrt(0.5)
        if axis == "x":  # yaw * (h, 0, h, 0)
            return [w * h, -z * h, w * h, z * h]
        return [w * h, -w * h, -z * h, z * h]  # yaw * (h, -h, 0, 0)

    def _add(
        self, name: str, kind: int, size: list[float], pos: Vec3, rgba: Colour, axis: str,
        emission: float = 0.0,
    ) -> None:  # fmt: skip
        mat = prop_material(self.spec, rgba, emission)
        self.spec.worldbody.add_geom(
            name=self.prefix + name, type=kind, size=size, pos=self._world(pos),
            quat=self._quat(axis), material=mat, contype=0, conaffinity=0,
        )  # fmt: skip

    def box(self, name: str, half: Vec3, pos: Vec3, rgba: Colour, emission: float = 0.0) -> None:
        """A box with half-sizes ``half`` centred at local ``pos`` (``emission``: self-lit)."""
        self._add(name, mujoco.mjtGeom.mjGEOM_BOX, list(half), pos, rgba, "z", emission)

    def cyl(
        self, name: str, radius: float, half_len: float, pos: Vec3, rgba: Colour, axis: str = "z"
    ) -> None:
        """A cylinder along local ``axis`` (x, y or z) centred at local ``pos``."""
        self._add(name, mujoco.mjtGeom.mjGEOM_CYLINDER, [radius, half_len, 0.0], pos, rgba, axis)

    def ball(self, name: str, radius: float, pos: Vec3, rgba: Colour) -> None:
        """A sphere centred at local ``pos``."""
        self._add(name, mujoco.mjtGeom.mjGEOM_SPHERE, [radius, 0.0, 0.0], pos, rgba, "z")


def prop_material(spec: mujoco.MjSpec, rgba: Colour, emission: float = 0.0) -> str:
    """A shared material per colour (a catalogue name or an RGBA) and emission."""
    if isinstance(rgba, str):
        key, value = rgba, color(rgba)
    else:
        key, value = "".join(f"{round(c * 255):02x}" for c in rgba), rgba
    glow = f"_glow{round(emission * 100)}" if emission else ""
    name = solid_material(spec, f"prop_{key}{glow}", value, specular=0.15)
    spec.material(name).emission = emission
    return name


def on_wall(
    spec: mujoco.MjSpec, name: str, env: EnvironmentSpec, side: str, along: float = 0.0
) -> PropPlacer:
    """A placer on the inside of a wall: x along the wall, y into the room, z up."""
    hs = env.room_half_size
    origin, yaw = {
        "north": ((-along, hs), 180.0),
        "south": ((along, -hs), 0.0),
        "east": ((hs, along), 90.0),
        "west": ((-hs, -along), -90.0),
    }[side]
    return PropPlacer(spec, f"{PROP_PREFIX}{name}/", origin, yaw)


def add_window(
    spec: mujoco.MjSpec, name: str, at: tuple[float, float], yaw_deg: float,
    size: tuple[float, float], z: float,
) -> None:  # fmt: skip
    """A daylight window (bright pane in a white frame) on a wall's inner face.

    Args:
        spec: Scene under construction.
        name: Geom name prefix of its parts.
        at: World (x, y) of the window centre on the wall's inner face.
        yaw_deg: Yaw of the wall normal (0: the wall is perpendicular to x).
        size: Width and height (m).
        z: Height of the window centre (m).
    """
    w, h = size[0] / 2, size[1] / 2
    p = PropPlacer(spec, f"{name}/", at, yaw_deg)
    inward = -1.0 if (at[0] * math.cos(p.yaw) + at[1] * math.sin(p.yaw)) > 0 else 1.0
    d = 0.012 * inward
    p.box("pane", (0.01, w, h), (d, 0.0, z), GLASS, emission=0.5)  # daylight outside
    white = "white"
    p.box("frame_top", (0.03, w + 0.05, 0.05), (2 * d, 0.0, z + h + 0.02), white)
    p.box("frame_bottom", (0.05, w + 0.05, 0.04), (3 * d, 0.0, z - h - 0.02), white)
    p.box("frame_left", (0.03, 0.05, h), (2 * d, -w - 0.02, z), white)
    p.box("frame_right", (0.03, 0.05, h), (2 * d, w + 0.02, z), white)
    p.box("mullion", (0.02, 0.02, h), (2 * d, 0.0, z), white)


def add_door(p: PropPlacer, along: float) -> None:
    p.box("door", (0.45, 0.025, 1.02), (along, 0.025, 1.02), "dark_wood")
    p.ball("door_knob", 0.035, (along + 0.35, 0.08, 1.0), "metal")


def add_frame(
    p: PropPlacer, name: str, along: float, z: float, half: tuple[float, float], art: Colour
) -> None:
    p.box(f"{name}_frame", (half[0] + 0.04, 0.015, half[1] + 0.04), (along, 0.015, z), "dark_wood")
    p.box(f"{name}_art", (half[0], 0.02, half[1]), (along, 0.02, z), art)
