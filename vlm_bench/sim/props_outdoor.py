"""Props of the outdoor environments: garden and yard."""

from __future__ import annotations

import mujoco

from vlm_bench.sim.prop_kit import BRICK, GLASS, LEAF, PROP_PREFIX, Colour, PropPlacer
from vlm_bench.types.world import EnvironmentSpec


def _tree(spec: mujoco.MjSpec, name: str, at: tuple[float, float], scale: float) -> None:
    t = PropPlacer(spec, f"{PROP_PREFIX}{name}/", at)
    t.cyl("trunk", 0.14 * scale, 1.0 * scale, (0.0, 0.0, 1.0 * scale), "brown")
    for i, (dx, dy, dz, r) in enumerate(
        ((0, 0, 2.6, 1.0), (0.5, 0.2, 2.2, 0.7), (-0.4, -0.3, 2.3, 0.75))
    ):
        t.ball(f"crown{i}", r * scale, (dx * scale, dy * scale, dz * scale), LEAF if i else "green")


def _picket_fence(p: PropPlacer, length: float, colour: Colour) -> None:
    count = int(length / 0.25)
    for k in range(count):
        p.box(f"picket{k}", (0.04, 0.015, 0.5), (-length / 2 + 0.25 * k, 0.0, 0.5), colour)
    for j, z in enumerate((0.3, 0.75)):
        p.box(f"rail{j}", (length / 2, 0.02, 0.04), (0.0, -0.03, z), colour)


def garden(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
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
        PropPlacer(spec, f"{PROP_PREFIX}bush{i}/", (x, y)).ball(
            "leaves", r, (0.0, 0.0, r * 0.75), LEAF
        )
    bed = PropPlacer(spec, f"{PROP_PREFIX}flower_bed/", (0.5, 5.4))
    bed.box("soil", (1.6, 0.45, 0.08), (0.0, 0.0, 0.08), "dirt")
    palette = ("red", "yellow", "pink", "purple", "white", "orange")
    for k in range(16):
        x, y = -1.45 + 0.19 * k, (-0.2, 0.2)[k % 2]
        bed.cyl(f"stem{k}", 0.01, 0.12, (x, y, 0.28), "green")
        bed.ball(f"flower{k}", 0.06, (x, y, 0.42), palette[k % len(palette)])
    _picket_fence(PropPlacer(spec, f"{PROP_PREFIX}fence_n/", (0.0, hs)), 2 * hs, "white")
    _picket_fence(PropPlacer(spec, f"{PROP_PREFIX}fence_w/", (-hs, 0.0), 90.0), 2 * hs, "white")
    bench = PropPlacer(spec, f"{PROP_PREFIX}bench/", (5.6, -1.2), 180.0)
    bench.box("seat", (0.22, 0.7, 0.03), (0.0, 0.0, 0.45), "wood")
    bench.box("back", (0.03, 0.7, 0.2), (0.2, 0.0, 0.75), "wood")
    for i, y in enumerate((-0.6, 0.6)):
        bench.box(f"leg{i}", (0.2, 0.03, 0.22), (0.0, y, 0.22), "black")
    shed = PropPlacer(spec, f"{PROP_PREFIX}shed/", (-7.5, -5.0), 90.0)
    shed.box("walls", (1.2, 1.0, 1.1), (0.0, 0.0, 1.1), "dark_wood")
    shed.box("roof", (1.35, 1.15, 0.06), (0.0, 0.0, 2.26), "dark_gray")
    shed.box("door", (0.4, 0.02, 0.9), (0.0, -1.01, 0.9), "wood")


def yard(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """A brick building with windows and a garage door, a board fence, a car, bins, lamp, cones."""
    hs = env.room_half_size
    b = PropPlacer(spec, f"{PROP_PREFIX}building/", (0.0, hs + 1.5))
    b.box("walls", (8.0, 1.5, 2.8), (0.0, 1.5, 2.8), BRICK)
    b.box("roof", (8.2, 1.7, 0.12), (0.0, 1.5, 5.66), "dark_gray")
    b.box("garage_door", (1.5, 0.03, 1.2), (2.5, 0.0, 1.2), "light_gray")
    for k in range(6):
        b.box(f"garage_rib{k}", (1.5, 0.035, 0.01), (2.5, 0.0, 0.35 * (k + 1)), "gray")
    for i, x in enumerate((-5.5, -2.5, 5.8)):
        for j, z in enumerate((1.5, 4.0)):
            b.box(f"window{i}{j}_frame", (0.65, 0.04, 0.6), (x, 0.0, z), "white")
            b.box(f"window{i}{j}", (0.55, 0.05, 0.5), (x, 0.0, z), GLASS)
    b.box("door", (0.5, 0.04, 1.05), (-4.0, 0.0, 1.05), "navy")
    fence = PropPlacer(spec, f"{PROP_PREFIX}fence_w/", (-hs, 0.0), 90.0)
    for k in range(16):
        fence.box(
            f"board{k}",
            (0.49, 0.03, 0.9),
            (-hs + 0.5 + k, 0.0, 0.9),
            "dark_wood" if k % 2 else "wood",
        )
    car = PropPlacer(spec, f"{PROP_PREFIX}car/", (6.5, 3.5), 100.0)
    car.box("body", (2.1, 0.85, 0.35), (0.0, 0.0, 0.65), "red")
    car.box("cabin", (1.1, 0.78, 0.3), (-0.2, 0.0, 1.28), (0.25, 0.3, 0.38, 1.0))
    for i, (x, y) in enumerate(((-1.3, -0.85), (-1.3, 0.85), (1.3, -0.85), (1.3, 0.85))):
        car.cyl(f"wheel{i}", 0.33, 0.12, (x, y, 0.33), "black", axis="y")
    for i, (x, c) in enumerate(((-6.2, "green"), (-5.4, "blue"), (-4.6, "dark_gray"))):
        binp = PropPlacer(spec, f"{PROP_PREFIX}bin{i}/", (x, hs - 1.2))
        binp.box("body", (0.3, 0.35, 0.5), (0.0, 0.0, 0.55), c)
        binp.box("lid", (0.32, 0.37, 0.03), (0.0, 0.0, 1.08), c)
    lamp = PropPlacer(spec, f"{PROP_PREFIX}street_lamp/", (5.0, -5.5))
    lamp.cyl("pole", 0.06, 2.0, (0.0, 0.0, 2.0), "dark_gray")
    lamp.box("head", (0.35, 0.12, 0.06), (-0.3, 0.0, 4.0), "dark_gray")
    for i, (x, y) in enumerate(((4.6, -1.8), (4.4, -0.8), (-3.2, -4.9))):
        cone = PropPlacer(spec, f"{PROP_PREFIX}cone{i}/", (x, y))
        cone.box("base", (0.2, 0.2, 0.02), (0.0, 0.0, 0.02), "orange")
        for k, r in enumerate((0.13, 0.1, 0.07, 0.045)):
            cone.cyl(
                f"ring{k}", r, 0.08, (0.0, 0.0, 0.12 + 0.16 * k), "white" if k == 2 else "orange"
            )
    planter = PropPlacer(spec, f"{PROP_PREFIX}planter/", (-5.0, -4.5))
    planter.box("box", (0.8, 0.3, 0.25), (0.0, 0.0, 0.25), "concrete")
    for k in range(3):
        planter.ball(f"shrub{k}", 0.28, (-0.5 + 0.5 * k, 0.0, 0.65), LEAF)
