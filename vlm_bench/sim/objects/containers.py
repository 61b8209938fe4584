"""Open containers: basket, storage box, parts bin, tray.

Walls and floors are at least 1.2 cm thick so objects dropped in stay inside without tunnelling.
"""

from __future__ import annotations

import math

import mujoco

from vlm_bench.sim.objects.builder_kit import (
    OBJECT_BUILDERS,
    PLAIN,
    Kit,
    Look,
    object_kit,
    shade,
)
from vlm_bench.sim.objects.frames import axis_angle
from vlm_bench.types.base import RGBA
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

WALL = 0.012  # wall and floor thickness (m)
SLOT: RGBA = (0.08, 0.08, 0.09, 1.0)  # colour of cut-outs (handle holes)


def open_box(
    kit: Kit,
    piece: str,
    size: tuple[float, float, float],
    look: Look,
    floor_look: Look | None = None,
    centre: tuple[float, float, float] = (0.0, 0.0, 0.0),
    wall: float = WALL,
) -> None:
    """A floor and four walls: outer size ``(lx, ly, h)`` with its bottom centre at ``centre``."""
    lx, ly, h = size
    cx, cy, cz = centre
    kit.box(
        f"{piece}_floor", (lx / 2, ly / 2, wall / 2), (cx, cy, cz + wall / 2), floor_look or look
    )
    hz, zc = (h - wall) / 2, cz + wall + (h - wall) / 2
    for name, sign in (("front", 1.0), ("back", -1.0)):
        pos = (cx + sign * (lx - wall) / 2, cy, zc)
        kit.box(f"{piece}_{name}", (wall / 2, ly / 2, hz), pos, look)
    for name, sign in (("left", 1.0), ("right", -1.0)):
        pos = (cx, cy + sign * (ly - wall) / 2, zc)
        kit.box(f"{piece}_{name}", (lx / 2 - wall, wall / 2, hz), pos, look)


def _ring(
    kit: Kit, piece: str, lx: float, ly: float, z0: float, z1: float, t: float, look: Look
) -> None:
    """A rectangular frame of width ``t`` (outer size ``lx`` × ``ly``) from ``z0`` to ``z1``."""
    hz, zc = (z1 - z0) / 2, (z0 + z1) / 2
    for name, sign in (("front", 1.0), ("back", -1.0)):
        kit.box(f"{piece}_{name}", (t / 2, ly / 2, hz), (sign * (lx - t) / 2, 0.0, zc), look)
    for name, sign in (("left", 1.0), ("right", -1.0)):
        kit.box(f"{piece}_{name}", (lx / 2 - t, t / 2, hz), (0.0, sign * (ly - t) / 2, zc), look)


@OBJECT_BUILDERS.register("basket")
def build_basket(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A slatted basket: solid base band, three slats with gaps, a top rim, woven ribs."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    look = kit.look(rgba)
    kit.box(
        "floor", (lx / 2 - WALL, ly / 2 - WALL, WALL / 2), (0.0, 0.0, WALL / 2), shade(rgba, 0.85)
    )
    base, rim = 0.028, 0.022
    _ring(kit, "band", lx, ly, 0.0, base, WALL, look)
    n = 3
    gap = (h - base - rim - n * 0.02) / (n + 1)
    for i in range(n):
        z0 = base + gap + i * (0.02 + gap)
        _ring(kit, f"slat{i}", lx, ly, z0, z0 + 0.02, WALL, look)
    _ring(kit, "rim", lx, ly, h - rim, h, WALL + 0.002, look)
    # Vertical ribs across the slats, slightly proud on the outside: the woven look.
    rib = kit.look(shade(rgba, 0.72))
    hz, zc = (h - base - rim) / 2, (h - rim + base) / 2
    for i, x in enumerate(_spread(lx - 0.06, 0.045)):
        for sign in (1.0, -1.0):
            pos = (x, sign * (ly / 2 - 0.0009), zc)
            kit.box(f"rib_y{i}_{int(sign)}", (0.004, 0.0012, hz), pos, rib, solid=False)
    for i, y in enumerate(_spread(ly - 0.06, 0.045)):
        for sign in (1.0, -1.0):
            pos = (sign * (lx / 2 - 0.0009), y, zc)
            kit.box(f"rib_x{i}_{int(sign)}", (0.0012, 0.004, hz), pos, rib, solid=False)
    for sign in (1.0, -1.0):  # handle holes in the rim of the short ends
        pos = (sign * (lx / 2 + 0.0003), 0.0, h - rim / 2)
        kit.box(f"handle_hole{int(sign)}", (0.0012, 0.035, 0.006), pos, SLOT, solid=False)
    return kit.finish(kind.mass)


def _spread(length: float, pitch: float) -> list[float]:
    """Evenly spaced positions over ``length`` centred on 0, about ``pitch`` apart."""
    n = max(1, round(length / pitch))
    return [-length / 2 + length * (i + 0.5) / n for i in range(n)]


@OBJECT_BUILDERS.register("storage_box")
def build_storage_box(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A plastic tote: solid walls inset under an overhanging rim, with a darker floor."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    lip = 0.01
    look = kit.look(rgba)
    open_box(kit, "tub", (lx - 2 * lip, ly - 2 * lip, h - 0.016), look, shade(rgba, 0.7))
    _ring(kit, "rim", lx, ly, h - 0.016, h, WALL + lip, kit.look(shade(rgba, 1.12)))
    for sign in (1.0, -1.0):  # grip slots under the rim of the short ends
        pos = (sign * (lx / 2 - lip + 0.0003), 0.0, h - 0.03)
        kit.box(f"grip{int(sign)}", (0.0008, 0.04, 0.007), pos, SLOT, solid=False)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("parts_bin")
def build_parts_bin(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A stackable parts bin: tall back, side walls sloping down to a low front with a label."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    front_h = 0.55 * h
    look = kit.look(rgba)
    kit.box("floor", (lx / 2, ly / 2, WALL / 2), (0.0, 0.0, WALL / 2), shade(rgba, 0.8))
    back_h = h - WALL
    kit.box(
        "back", (WALL / 2, ly / 2, back_h / 2), (-(lx - WALL) / 2, 0.0, WALL + back_h / 2), look
    )
    low_h = front_h - WALL
    pos = ((lx - WALL) / 2, 0.0, WALL + low_h / 2)
    kit.box("front", (WALL / 2, ly / 2, low_h / 2), pos, look)
    inner = lx / 2 - WALL
    # Sides: a low straight part plus a tilted plank whose top edge runs back-top → front-top.
    rise = h - front_h
    length = math.hypot(2 * inner, rise)
    tilt = math.degrees(math.atan2(rise, 2 * inner))
    thick = 0.028
    drop = thick / 2 / math.cos(math.radians(tilt))
    for name, sign in (("left", 1.0), ("right", -1.0)):
        y = sign * (ly - WALL) / 2
        kit.box(f"{name}_low", (inner, WALL / 2, low_h / 2), (0.0, y, WALL + low_h / 2), look)
        pos = (0.0, y, (h + front_h) / 2 - drop)
        # 0.3 mm thinner than the low wall so their faces are not coplanar.
        half = (length / 2 - thick / 2 * math.sin(math.radians(tilt)), WALL / 2 - 0.0003, thick / 2)
        kit.box(f"{name}_slope", half, pos, look, axis_angle((0.0, 1.0, 0.0), tilt))
    label = (0.96, 0.96, 0.94, 1.0)
    kit.box(
        "label",
        (0.0008, ly * 0.3, front_h * 0.25),
        (lx / 2 + 0.0002, 0.0, front_h * 0.55),
        label,
        solid=False,
    )
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("tray")
def build_tray(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A shallow tray: floor, low rim and hand slots in the short ends."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    open_box(kit, "tray", (lx, ly, h), kit.look(rgba), shade(rgba, 1.15))
    for sign in (1.0, -1.0):
        pos = (sign * (lx / 2 + 0.0003), 0.0, h * 0.62)
        kit.box(f"slot{int(sign)}", (0.0008, 0.045, 0.004), pos, SLOT, solid=False)
    return kit.finish(kind.mass)
