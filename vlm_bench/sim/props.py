"""Static decorative props that make each environment variant recognisable.

Props are visual-only geoms in the world body named ``prop/<what>/<part>``; every one stays farther
than :data:`KEEP_OUT_RADIUS` horizontally from the origin (against the walls indoors), so they never
block cameras looking at the work area. Composite props are laid out in a local frame
(:class:`Placer`); indoors that frame sits on a wall: x along the wall, y into the room, z up.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco

from vlm_bench.catalog.world_catalog import color
from vlm_bench.sim.materials import solid_material
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.world import EnvironmentSpec

PROP_PREFIX = "prop/"
KEEP_OUT_RADIUS = 3.8
Colour = str | RGBA

_GLASS: RGBA = (0.62, 0.78, 0.92, 1.0)
_LEAF: RGBA = (0.14, 0.42, 0.16, 1.0)
_BRICK: RGBA = (0.62, 0.28, 0.2, 1.0)
_SCREEN: RGBA = (0.03, 0.03, 0.05, 1.0)
_CARDBOARD: RGBA = (0.72, 0.55, 0.35, 1.0)


class Placer:
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
        mat = _material(self.spec, rgba, emission)
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


def _material(spec: mujoco.MjSpec, rgba: Colour, emission: float = 0.0) -> str:
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
) -> Placer:
    """A placer on the inside of a wall: x along the wall, y into the room, z up."""
    hs = env.room_half_size
    origin, yaw = {
        "north": ((-along, hs), 180.0),
        "south": ((along, -hs), 0.0),
        "east": ((hs, along), 90.0),
        "west": ((-hs, -along), -90.0),
    }[side]
    return Placer(spec, f"{PROP_PREFIX}{name}/", origin, yaw)


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
    p = Placer(spec, f"{name}/", at, yaw_deg)
    inward = -1.0 if (at[0] * math.cos(p.yaw) + at[1] * math.sin(p.yaw)) > 0 else 1.0
    d = 0.012 * inward
    p.box("pane", (0.01, w, h), (d, 0.0, z), _GLASS, emission=0.5)  # daylight outside
    white = "white"
    p.box("frame_top", (0.03, w + 0.05, 0.05), (2 * d, 0.0, z + h + 0.02), white)
    p.box("frame_bottom", (0.05, w + 0.05, 0.04), (3 * d, 0.0, z - h - 0.02), white)
    p.box("frame_left", (0.03, 0.05, h), (2 * d, -w - 0.02, z), white)
    p.box("frame_right", (0.03, 0.05, h), (2 * d, w + 0.02, z), white)
    p.box("mullion", (0.02, 0.02, h), (2 * d, 0.0, z), white)


def _door(p: Placer, along: float) -> None:
    p.box("door", (0.45, 0.025, 1.02), (along, 0.025, 1.02), "dark_wood")
    p.ball("door_knob", 0.035, (along + 0.35, 0.08, 1.0), "metal")


def _frame(
    p: Placer, name: str, along: float, z: float, half: tuple[float, float], art: Colour
) -> None:
    p.box(f"{name}_frame", (half[0] + 0.04, 0.015, half[1] + 0.04), (along, 0.015, z), "dark_wood")
    p.box(f"{name}_art", (half[0], 0.02, half[1]), (along, 0.02, z), art)


def _kitchen(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Fitted L-shaped counter with sink, wall cabinets, fridge, microwave; shelves; a door."""
    hs = env.room_half_size
    n = on_wall(spec, "counter_n", env, "north")  # local x = -world x
    n.box("base", (3.6, 0.29, 0.43), (0.9, 0.3, 0.43), "white")
    n.box("top", (3.62, 0.31, 0.025), (0.9, 0.31, 0.885), "dark_gray")
    for i in range(12):
        n.box(f"door_gap{i}", (0.006, 0.005, 0.36), (-2.4 + 0.6 * i, 0.595, 0.46), "gray")
        n.box(f"handle{i}", (0.06, 0.012, 0.012), (-2.55 + 0.6 * i, 0.6, 0.74), "metal")
    n.box("sink", (0.36, 0.23, 0.012), (0.0, 0.3, 0.91), "metal")
    n.cyl("tap", 0.018, 0.14, (0.0, 0.09, 1.05), "metal")
    n.cyl("spout", 0.015, 0.1, (0.0, 0.17, 1.18), "metal", axis="y")
    for i, (x, hx) in enumerate(((-1.9, 0.8), (2.8, 1.7))):
        n.box(f"wall_cab{i}", (hx, 0.17, 0.36), (x, 0.17, 1.85), "white")
        n.box(f"wall_cab_line{i}", (0.006, 0.005, 0.33), (x, 0.345, 1.85), "gray")
    n.box("fridge", (0.4, 0.32, 0.95), (-3.15, 0.32, 0.95), "metal")
    n.box("fridge_gap", (0.4, 0.005, 0.006), (-3.15, 0.645, 1.25), "dark_gray")
    n.box("fridge_handle", (0.015, 0.02, 0.3), (-2.82, 0.66, 1.0), "black")
    n.box("microwave", (0.26, 0.19, 0.15), (2.0, 0.25, 1.06), "black")
    n.box("microwave_door", (0.17, 0.005, 0.11), (1.95, 0.44, 1.06), (0.2, 0.22, 0.25, 1.0))
    n.cyl("kettle", 0.09, 0.12, (-1.5, 0.3, 1.03), "red")
    w = on_wall(spec, "counter_w", env, "west")  # local x = -world y
    w.box("base", (1.95, 0.29, 0.43), (-1.95, 0.3, 0.43), "white")
    w.box("top", (1.95, 0.31, 0.025), (-1.95, 0.31, 0.885), "dark_gray")
    w.cyl("bowl", 0.14, 0.04, (-2.6, 0.3, 0.95), "blue")
    for i, c in enumerate(("yellow", "orange", "red")):
        w.ball(f"fruit{i}", 0.045, (-2.65 + 0.07 * i, 0.3, 1.02), c)
    w.box("pantry", (0.5, 0.3, 1.05), (1.6, 0.3, 1.05), "white")
    w.box("pantry_gap", (0.006, 0.005, 1.0), (1.6, 0.605, 1.05), "gray")
    s = on_wall(spec, "shelf_s", env, "south")
    for k, z in enumerate((1.35, 1.75)):
        s.box(f"board{k}", (0.9, 0.13, 0.015), (-1.5, 0.13, z), "wood")
        for i in range(5):
            s.cyl(
                f"jar{k}_{i}",
                0.05,
                0.08,
                (-2.2 + 0.35 * i, 0.12, z + 0.095),
                ("teal", "orange", "white")[i % 3],
            )
    s.cyl("rail", 0.012, 0.7, (1.6, 0.12, 1.95), "metal", axis="x")
    for i, (c, r) in enumerate((("dark_gray", 0.13), ("orange", 0.11), ("metal", 0.09))):
        s.cyl(f"pot{i}", r, 0.07, (1.1 + 0.45 * i, 0.15, 1.7), c)
    s.cyl("clock", 0.2, 0.015, (-0.5, 0.015, 2.1), "white", axis="y")
    s.cyl("clock_rim", 0.22, 0.01, (-0.5, 0.006, 2.1), "black", axis="y")
    s.cyl("bin", 0.18, 0.3, (2.6, 0.25, 0.3), "metal")
    e = on_wall(spec, "oven_wall", env, "east")  # local x = world y
    e.box("base", (1.2, 0.29, 0.43), (-0.7, 0.3, 0.43), "white")
    e.box("top", (1.22, 0.31, 0.025), (-0.7, 0.31, 0.885), "dark_gray")
    e.box("cutting_board", (0.22, 0.15, 0.012), (-1.2, 0.3, 0.92), "wood")
    e.box("knife_block", (0.06, 0.1, 0.12), (-0.8, 0.2, 1.03), "black")
    e.box("dish_rack", (0.25, 0.17, 0.06), (-0.1, 0.3, 0.97), "metal")
    for i in range(4):
        e.cyl(f"plate{i}", 0.1, 0.006, (-0.25 + 0.08 * i, 0.3, 1.08), "white", axis="x")
    e.box("oven_column", (0.35, 0.3, 1.05), (1.9, 0.3, 1.05), "white")
    e.box("oven_door", (0.28, 0.01, 0.22), (1.9, 0.605, 0.85), "black")
    e.box("oven_handle", (0.24, 0.02, 0.012), (1.9, 0.62, 1.1), "metal")
    e.box("micro_door", (0.28, 0.01, 0.14), (1.9, 0.605, 1.45), "black")
    _door(e, -hs + 1.0)


def _living_room(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Sofa with cushions and pictures, TV on a console, bookshelf, plant, lamps, corner rug."""
    n = on_wall(spec, "sofa", env, "north")
    n.box("back", (1.2, 0.1, 0.42), (0.0, 0.12, 0.42), "teal")
    n.box("seat", (1.0, 0.27, 0.12), (0.0, 0.36, 0.32), "teal")
    n.box("base", (1.2, 0.3, 0.1), (0.0, 0.32, 0.12), "navy")
    for side in (-1, 1):
        n.box(f"arm{side}", (0.11, 0.3, 0.3), (side * 1.1, 0.32, 0.3), "teal")
    for i, c in enumerate(("orange", "yellow", "orange")):
        n.box(f"pillow{i}", (0.18, 0.06, 0.16), (-0.6 + 0.6 * i, 0.28, 0.58), c)
    lamp = on_wall(spec, "floor_lamp", env, "north", along=-1.75)
    lamp.cyl("base", 0.16, 0.015, (0.0, 0.3, 0.015), "black")
    lamp.cyl("pole", 0.015, 0.75, (0.0, 0.3, 0.77), "black")
    lamp.cyl("shade", 0.2, 0.16, (0.0, 0.3, 1.6), "cream")
    e = on_wall(spec, "tv", env, "east")
    e.box("console", (1.0, 0.22, 0.25), (0.0, 0.22, 0.25), "dark_wood")
    e.box("screen", (0.8, 0.03, 0.46), (0.0, 0.05, 1.25), _SCREEN)
    for side in (-1, 1):
        e.box(f"speaker{side}", (0.1, 0.1, 0.45), (side * 1.3, 0.15, 0.45), "black")
    w = on_wall(spec, "bookshelf", env, "west", along=1.7)
    w.box("back", (0.65, 0.02, 1.0), (0.0, 0.02, 1.0), "dark_wood")
    for side in (-1, 1):
        w.box(f"side{side}", (0.02, 0.18, 1.0), (side * 0.65, 0.18, 1.0), "dark_wood")
    palette = ("red", "blue", "green", "cream", "navy", "orange", "purple")
    for k in range(5):
        w.box(f"board{k}", (0.65, 0.18, 0.015), (0.0, 0.18, 0.02 + 0.48 * k), "dark_wood")
        if k < 4:
            for i in range(8):
                h = 0.15 + 0.03 * ((i * 7 + k) % 3)
                c = palette[(i + 2 * k) % len(palette)]
                w.box(
                    f"book{k}_{i}",
                    (0.05, 0.13, h),
                    (-0.53 + 0.15 * i, 0.17, 0.035 + 0.48 * k + h),
                    c,
                )
    plant = on_wall(spec, "plant", env, "west", along=-2.9)
    plant.cyl("pot", 0.2, 0.2, (0.0, 0.3, 0.2), "orange")
    for i, (dx, dz, r) in enumerate(((0.0, 0.75, 0.3), (-0.12, 0.55, 0.22), (0.12, 0.6, 0.24))):
        plant.ball(f"leaves{i}", r, (dx, 0.33, dz), _LEAF)
    s = on_wall(spec, "wall_s", env, "south")
    _frame(s, "pic_a", -0.2, 1.6, (0.35, 0.25), "blue")
    _frame(s, "pic_b", 0.7, 1.6, (0.35, 0.25), "orange")
    _frame(s, "pic_c", 2.1, 1.5, (0.6, 0.4), "green")
    _door(s, -2.6)
    hs = env.room_half_size
    rug = Placer(spec, f"{PROP_PREFIX}rug/", (-(hs - 0.9), -(hs - 0.9)), -45.0)
    rug.box("outer", (0.7, 0.5, 0.004), (0.0, 0.0, 0.004), "red")
    rug.box("inner", (0.55, 0.36, 0.004), (0.0, 0.0, 0.006), "cream")
    rug.cyl("pouf", 0.25, 0.2, (0.0, 0.0, 0.2), "purple")


def _floor_lines(spec: mujoco.MjSpec, env: EnvironmentSpec, inset: float) -> None:
    """Yellow safety lines parallel to the walls, ``inset`` m into the room."""
    half = env.room_half_size - inset
    for side in ("north", "south", "east", "west"):
        on_wall(spec, f"safety_line_{side}", env, side).box(
            "line", (half, 0.04, 0.002), (0.0, inset, 0.002), "yellow"
        )


def _workshop(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Workbench and pegboard, tool chest, shelving, compressor, gas bottles, machines, drums."""
    n = on_wall(spec, "workbench", env, "north")
    n.box("top", (1.5, 0.38, 0.03), (0.0, 0.4, 0.9), "wood")
    n.box("shelf", (1.45, 0.34, 0.015), (0.0, 0.4, 0.22), "gray")
    for i, (x, y) in enumerate(((-1.42, 0.08), (1.42, 0.08), (-1.42, 0.72), (1.42, 0.72))):
        n.box(f"leg{i}", (0.03, 0.03, 0.435), (x, y, 0.435), "dark_gray")
    n.box("pegboard", (1.4, 0.01, 0.45), (0.0, 0.01, 1.45), "tan")
    for i in range(6):
        n.box(f"wrench{i}", (0.014, 0.01, 0.1 + 0.02 * i), (-1.2 + 0.13 * i, 0.03, 1.5), "metal")
    for i, c in enumerate(("red", "yellow", "blue", "red")):
        n.box(f"driver{i}", (0.014, 0.014, 0.06), (-0.2 + 0.1 * i, 0.035, 1.62), c)
        n.box(f"driver_shaft{i}", (0.005, 0.005, 0.08), (-0.2 + 0.1 * i, 0.035, 1.48), "metal")
    n.box("hammer_handle", (0.02, 0.015, 0.16), (0.55, 0.035, 1.45), "wood")
    n.box("hammer_head", (0.08, 0.02, 0.025), (0.55, 0.04, 1.62), "dark_gray")
    n.box("saw", (0.28, 0.006, 0.07), (1.0, 0.03, 1.3), "metal")
    n.box("vise", (0.1, 0.12, 0.07), (1.25, 0.68, 1.0), "blue")
    n.box("toolbox", (0.25, 0.13, 0.1), (-0.9, 0.45, 1.03), "red")
    chest = on_wall(spec, "tool_chest", env, "east", along=-2.2)
    chest.box("body", (0.45, 0.3, 0.55), (0.0, 0.3, 0.63), "red")
    for k in range(5):
        chest.box(f"drawer{k}", (0.43, 0.006, 0.004), (0.0, 0.605, 0.25 + 0.19 * k), "black")
        chest.box(f"handle{k}", (0.3, 0.015, 0.01), (0.0, 0.61, 0.34 + 0.19 * k), "metal")
    for i, x in enumerate((-0.38, 0.38)):
        chest.cyl(f"wheel{i}", 0.04, 0.02, (x, 0.3, 0.04), "black", axis="x")
    rack = on_wall(spec, "shelving", env, "east", along=1.4)
    for i, x in enumerate((-0.9, 0.9)):
        for j, y in enumerate((0.05, 0.55)):
            rack.box(f"post{i}{j}", (0.02, 0.02, 1.0), (x, y, 1.0), "gray")
    for k in range(4):
        z = 0.12 + 0.6 * k
        rack.box(f"shelf{k}", (0.92, 0.28, 0.012), (0.0, 0.3, z), "metal")
        for i in range(3):
            c = ("blue", "yellow", "red", "green")[(i + k) % 4]
            rack.box(f"bin{k}_{i}", (0.24, 0.22, 0.1), (-0.6 + 0.6 * i, 0.3, z + 0.11), c)
    comp = on_wall(spec, "compressor", env, "west", along=1.5)
    comp.cyl("tank", 0.25, 0.5, (0.0, 0.4, 0.35), "red", axis="x")
    comp.box("motor", (0.2, 0.15, 0.12), (-0.15, 0.4, 0.72), "dark_gray")
    comp.cyl("gauge", 0.05, 0.01, (0.25, 0.4, 0.63), "white")
    gas = on_wall(spec, "gas_bottles", env, "west", along=-0.8)
    for i, c in enumerate(("green", "gray", "blue")):
        gas.cyl(f"bottle{i}", 0.11, 0.62, (-0.3 * i, 0.2, 0.62), c)
        gas.ball(f"cap{i}", 0.07, (-0.3 * i, 0.2, 1.27), "metal")
    press = on_wall(spec, "drill_press", env, "south", along=1.6)
    press.box("base", (0.25, 0.22, 0.04), (0.0, 0.3, 0.04), "teal")
    press.cyl("column", 0.045, 0.85, (0.0, 0.15, 0.9), "metal")
    press.box("head", (0.14, 0.28, 0.16), (0.0, 0.3, 1.62), "teal")
    press.cyl("chuck", 0.03, 0.08, (0.0, 0.45, 1.38), "metal")
    press.box("table", (0.16, 0.16, 0.015), (0.0, 0.45, 0.9), "dark_gray")
    lathe = on_wall(spec, "lathe", env, "south", along=-3.0)
    for i, x in enumerate((-0.55, 0.55)):
        lathe.box(f"pedestal{i}", (0.16, 0.2, 0.4), (x, 0.3, 0.4), "teal")
    lathe.box("bed", (0.75, 0.16, 0.06), (0.0, 0.3, 0.86), "dark_gray")
    lathe.box("headstock", (0.17, 0.18, 0.16), (-0.55, 0.3, 1.08), "teal")
    lathe.cyl("chuck", 0.09, 0.05, (-0.33, 0.3, 1.08), "metal", axis="x")
    lathe.box("tailstock", (0.08, 0.1, 0.1), (0.6, 0.3, 1.02), "teal")
    ext = on_wall(spec, "extinguisher", env, "south", along=-1.0)
    ext.cyl("body", 0.08, 0.25, (0.0, 0.1, 0.55), "red")
    ext.box("sign", (0.15, 0.01, 0.15), (0.0, 0.01, 1.15), "red")
    hs = env.room_half_size
    for i, (x, y) in enumerate(((hs - 0.45, -(hs - 0.45)), (hs - 1.1, -(hs - 0.45)))):
        drum = Placer(spec, f"{PROP_PREFIX}drum{i}/", (x, y))
        drum.cyl("body", 0.29, 0.44, (0.0, 0.0, 0.44), "blue")
        drum.cyl("lid", 0.27, 0.01, (0.0, 0.0, 0.885), "metal")
    _floor_lines(spec, env, 1.1)


def _rack(p: Placer, bays: int) -> None:
    """Pallet racking: blue uprights, orange beams, three levels of pallets and loads."""
    length = 2.4 * bays
    for k in range(bays + 1):
        for j, y in enumerate((0.12, 1.12)):
            p.box(f"upright{k}{j}", (0.04, 0.04, 1.7), (-length / 2 + 2.4 * k, y, 1.7), "blue")
    for lv, z in enumerate((0.15, 1.25, 2.35)):
        for j, y in enumerate((0.12, 1.12)):
            p.box(f"beam{lv}{j}", (length / 2, 0.03, 0.05), (0.0, y, z), "orange")
        for b in range(bays * 2):
            x = -length / 2 + 0.6 + 1.2 * b
            p.box(f"pallet{lv}_{b}", (0.5, 0.5, 0.06), (x, 0.62, z + 0.11), "wood")
            kind = (b + 2 * lv) % 4
            if kind == 3:
                continue
            rgba: Colour = (_CARDBOARD, "cream", _CARDBOARD)[kind]
            top = 0.3 if kind == 1 else 0.2
            p.box(f"load{lv}_{b}", (0.45, 0.45, top), (x, 0.62, z + 0.17 + top), rgba)


def _warehouse(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Pallet racks on two walls, a forklift, pallet stacks, a dock door with bollards, drums."""
    _rack(on_wall(spec, "rack_n", env, "north"), 3)
    _rack(on_wall(spec, "rack_e", env, "east", along=-0.8), 2)
    f = on_wall(spec, "forklift", env, "west", along=-1.6)
    f.box("body", (0.6, 0.42, 0.3), (0.0, 0.9, 0.5), "yellow")
    f.box("counterweight", (0.15, 0.42, 0.3), (-0.72, 0.9, 0.5), "black")
    f.box("seat", (0.15, 0.2, 0.12), (-0.2, 0.9, 0.92), "black")
    for i, (x, y) in enumerate(((-0.4, 0.52), (-0.4, 1.28), (0.45, 0.52), (0.45, 1.28))):
        f.box(f"guard_post{i}", (0.025, 0.025, 0.5), (x, y, 1.3), "dark_gray")
        f.cyl(f"wheel{i}", 0.2, 0.08, (x, 0.42 if y < 0.9 else 1.38, 0.2), "black", axis="y")
    f.box("guard_roof", (0.45, 0.42, 0.02), (0.02, 0.9, 1.82), "dark_gray")
    for i, y in enumerate((0.65, 1.15)):
        f.box(f"mast{i}", (0.04, 0.04, 1.1), (0.7, y, 1.1), "black")
        f.box(f"fork{i}", (0.45, 0.05, 0.02), (1.2, y, 0.1), "dark_gray")
    stack = on_wall(spec, "pallet_stack", env, "west", along=2.5)
    for k in range(6):
        stack.box(f"pallet{k}", (0.6, 0.5, 0.06), (0.01 * (k % 2), 0.6, 0.07 + 0.14 * k), "wood")
    dock = on_wall(spec, "dock_door", env, "south", along=0.5)
    dock.box("panel", (1.6, 0.03, 1.6), (0.0, 0.03, 1.6), "light_gray")
    for k in range(10):
        dock.box(f"rib{k}", (1.6, 0.035, 0.012), (0.0, 0.035, 0.3 * (k + 1)), "gray")
    for i, x in enumerate((-1.75, 1.75)):
        dock.box(f"jamb{i}", (0.1, 0.05, 1.7), (x, 0.05, 1.7), "yellow")
        dock.cyl(f"bollard{i}", 0.09, 0.5, (x, 0.7, 0.5), "yellow")
    hs = env.room_half_size
    for i, c in enumerate(("red", "red", "blue")):
        drum = Placer(spec, f"{PROP_PREFIX}drum{i}/", (hs - 0.45 - 0.62 * i, -(hs - 0.45)))
        drum.cyl("body", 0.29, 0.44, (0.0, 0.0, 0.44), c)
        drum.cyl("lid", 0.27, 0.01, (0.0, 0.0, 0.885), "metal")
    _floor_lines(spec, env, 1.55)


def _tree(spec: mujoco.MjSpec, name: str, at: tuple[float, float], scale: float) -> None:
    t = Placer(spec, f"{PROP_PREFIX}{name}/", at)
    t.cyl("trunk", 0.14 * scale, 1.0 * scale, (0.0, 0.0, 1.0 * scale), "brown")
    for i, (dx, dy, dz, r) in enumerate(
        ((0, 0, 2.6, 1.0), (0.5, 0.2, 2.2, 0.7), (-0.4, -0.3, 2.3, 0.75))
    ):
        t.ball(
            f"crown{i}", r * scale, (dx * scale, dy * scale, dz * scale), _LEAF if i else "green"
        )


def _picket_fence(p: Placer, length: float, colour: Colour) -> None:
    count = int(length / 0.25)
    for k in range(count):
        p.box(f"picket{k}", (0.04, 0.015, 0.5), (-length / 2 + 0.25 * k, 0.0, 0.5), colour)
    for j, z in enumerate((0.3, 0.75)):
        p.box(f"rail{j}", (length / 2, 0.02, 0.04), (0.0, -0.03, z), colour)


def _garden(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Trees, bushes, a flower bed, a white picket fence, a bench and a garden shed."""
    hs = env.room_half_size
    trees = (
        (6.5, 5.0, 1.1),
        (-7.0, 3.5, 1.3),
        (-5.5, -6.5, 1.0),
        (7.5, -5.5, 1.2),
        (1.5, 9.5, 1.4),
    )
    for i, (x, y, s) in enumerate(trees):
        _tree(spec, f"tree{i}", (x, y), s)
    bushes = (
        (4.8, 1.5, 0.55),
        (-4.7, -1.0, 0.6),
        (0.8, -5.0, 0.5),
        (-2.6, 4.7, 0.5),
        (4.4, -3.3, 0.45),
    )
    for i, (x, y, r) in enumerate(bushes):
        Placer(spec, f"{PROP_PREFIX}bush{i}/", (x, y)).ball(
            "leaves", r, (0.0, 0.0, r * 0.75), _LEAF
        )
    bed = Placer(spec, f"{PROP_PREFIX}flower_bed/", (0.5, 5.4))
    bed.box("soil", (1.6, 0.45, 0.08), (0.0, 0.0, 0.08), "dirt")
    palette = ("red", "yellow", "pink", "purple", "white", "orange")
    for k in range(16):
        x, y = -1.45 + 0.19 * k, (-0.2, 0.2)[k % 2]
        bed.cyl(f"stem{k}", 0.01, 0.12, (x, y, 0.28), "green")
        bed.ball(f"flower{k}", 0.06, (x, y, 0.42), palette[k % len(palette)])
    _picket_fence(Placer(spec, f"{PROP_PREFIX}fence_n/", (0.0, hs)), 2 * hs, "white")
    _picket_fence(Placer(spec, f"{PROP_PREFIX}fence_w/", (-hs, 0.0), 90.0), 2 * hs, "white")
    bench = Placer(spec, f"{PROP_PREFIX}bench/", (5.6, -1.2), 180.0)
    bench.box("seat", (0.22, 0.7, 0.03), (0.0, 0.0, 0.45), "wood")
    bench.box("back", (0.03, 0.7, 0.2), (0.2, 0.0, 0.75), "wood")
    for i, y in enumerate((-0.6, 0.6)):
        bench.box(f"leg{i}", (0.2, 0.03, 0.22), (0.0, y, 0.22), "black")
    shed = Placer(spec, f"{PROP_PREFIX}shed/", (-7.5, -5.0), 90.0)
    shed.box("walls", (1.2, 1.0, 1.1), (0.0, 0.0, 1.1), "dark_wood")
    shed.box("roof", (1.35, 1.15, 0.06), (0.0, 0.0, 2.26), "dark_gray")
    shed.box("door", (0.4, 0.02, 0.9), (0.0, -1.01, 0.9), "wood")


def _yard(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """A brick building with windows and a garage door, a board fence, a car, bins, lamp, cones."""
    hs = env.room_half_size
    b = Placer(spec, f"{PROP_PREFIX}building/", (0.0, hs + 1.5))
    b.box("walls", (8.0, 1.5, 2.8), (0.0, 1.5, 2.8), _BRICK)
    b.box("roof", (8.2, 1.7, 0.12), (0.0, 1.5, 5.66), "dark_gray")
    b.box("garage_door", (1.5, 0.03, 1.2), (2.5, 0.0, 1.2), "light_gray")
    for k in range(6):
        b.box(f"garage_rib{k}", (1.5, 0.035, 0.01), (2.5, 0.0, 0.35 * (k + 1)), "gray")
    for i, x in enumerate((-5.5, -2.5, 5.8)):
        for j, z in enumerate((1.5, 4.0)):
            b.box(f"window{i}{j}_frame", (0.65, 0.04, 0.6), (x, 0.0, z), "white")
            b.box(f"window{i}{j}", (0.55, 0.05, 0.5), (x, 0.0, z), _GLASS)
    b.box("door", (0.5, 0.04, 1.05), (-4.0, 0.0, 1.05), "navy")
    fence = Placer(spec, f"{PROP_PREFIX}fence_w/", (-hs, 0.0), 90.0)
    for k in range(16):
        fence.box(
            f"board{k}",
            (0.49, 0.03, 0.9),
            (-hs + 0.5 + k, 0.0, 0.9),
            "dark_wood" if k % 2 else "wood",
        )
    car = Placer(spec, f"{PROP_PREFIX}car/", (6.5, 3.5), 100.0)
    car.box("body", (2.1, 0.85, 0.35), (0.0, 0.0, 0.65), "red")
    car.box("cabin", (1.1, 0.78, 0.3), (-0.2, 0.0, 1.28), (0.25, 0.3, 0.38, 1.0))
    for i, (x, y) in enumerate(((-1.3, -0.85), (-1.3, 0.85), (1.3, -0.85), (1.3, 0.85))):
        car.cyl(f"wheel{i}", 0.33, 0.12, (x, y, 0.33), "black", axis="y")
    for i, (x, c) in enumerate(((-6.2, "green"), (-5.4, "blue"), (-4.6, "dark_gray"))):
        binp = Placer(spec, f"{PROP_PREFIX}bin{i}/", (x, hs - 1.2))
        binp.box("body", (0.3, 0.35, 0.5), (0.0, 0.0, 0.55), c)
        binp.box("lid", (0.32, 0.37, 0.03), (0.0, 0.0, 1.08), c)
    lamp = Placer(spec, f"{PROP_PREFIX}street_lamp/", (5.0, -5.5))
    lamp.cyl("pole", 0.06, 2.0, (0.0, 0.0, 2.0), "dark_gray")
    lamp.box("head", (0.35, 0.12, 0.06), (-0.3, 0.0, 4.0), "dark_gray")
    for i, (x, y) in enumerate(((4.6, -1.8), (4.4, -0.8), (-3.2, -4.9))):
        cone = Placer(spec, f"{PROP_PREFIX}cone{i}/", (x, y))
        cone.box("base", (0.2, 0.2, 0.02), (0.0, 0.0, 0.02), "orange")
        for k, r in enumerate((0.13, 0.1, 0.07, 0.045)):
            cone.cyl(
                f"ring{k}", r, 0.08, (0.0, 0.0, 0.12 + 0.16 * k), "white" if k == 2 else "orange"
            )
    planter = Placer(spec, f"{PROP_PREFIX}planter/", (-5.0, -4.5))
    planter.box("box", (0.8, 0.3, 0.25), (0.0, 0.0, 0.25), "concrete")
    for k in range(3):
        planter.ball(f"shrub{k}", 0.28, (-0.5 + 0.5 * k, 0.0, 0.65), _LEAF)


_BY_NAME: dict[str, Callable[[mujoco.MjSpec, EnvironmentSpec], None]] = {
    "household_kitchen": _kitchen,
    "household_living_room": _living_room,
    "industrial_workshop": _workshop,
    "industrial_warehouse": _warehouse,
    "outdoor_garden": _garden,
    "outdoor_yard": _yard,
}
_BY_TYPE = {"household": _living_room, "industrial": _workshop, "outdoor": _garden}


def add_props(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Add the decorative props of an environment variant (by variant name, else by type)."""
    builder = _BY_NAME.get(env.name, _BY_TYPE[env.type])
    builder(spec, env)
