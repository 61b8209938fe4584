"""Props of the indoor environments: kitchen and living room (household), workshop and warehouse
(industrial)."""

from __future__ import annotations

import mujoco

from vlm_bench.sim.prop_kit import (
    CARDBOARD,
    LEAF,
    PROP_PREFIX,
    SCREEN,
    Colour,
    PropPlacer,
    add_door,
    add_frame,
    on_wall,
)
from vlm_bench.types.world import EnvironmentSpec


def kitchen(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
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
    add_door(e, -hs + 1.0)


def living_room(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
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
    e.box("screen", (0.8, 0.03, 0.46), (0.0, 0.05, 1.25), SCREEN)
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
        plant.ball(f"leaves{i}", r, (dx, 0.33, dz), LEAF)
    s = on_wall(spec, "wall_s", env, "south")
    add_frame(s, "pic_a", -0.2, 1.6, (0.35, 0.25), "blue")
    add_frame(s, "pic_b", 0.7, 1.6, (0.35, 0.25), "orange")
    add_frame(s, "pic_c", 2.1, 1.5, (0.6, 0.4), "green")
    add_door(s, -2.6)
    hs = env.room_half_size
    rug = PropPlacer(spec, f"{PROP_PREFIX}rug/", (-(hs - 0.9), -(hs - 0.9)), -45.0)
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


def workshop(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
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
        drum = PropPlacer(spec, f"{PROP_PREFIX}drum{i}/", (x, y))
        drum.cyl("body", 0.29, 0.44, (0.0, 0.0, 0.44), "blue")
        drum.cyl("lid", 0.27, 0.01, (0.0, 0.0, 0.885), "metal")
    _floor_lines(spec, env, 1.1)


def _rack(p: PropPlacer, bays: int) -> None:
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
            rgba: Colour = (CARDBOARD, "cream", CARDBOARD)[kind]
            top = 0.3 if kind == 1 else 0.2
            p.box(f"load{lv}_{b}", (0.45, 0.45, top), (x, 0.62, z + 0.17 + top), rgba)


def warehouse(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
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
        drum = PropPlacer(spec, f"{PROP_PREFIX}drum{i}/", (hs - 0.45 - 0.62 * i, -(hs - 0.45)))
        drum.cyl("body", 0.29, 0.44, (0.0, 0.0, 0.44), c)
        drum.cyl("lid", 0.27, 0.01, (0.0, 0.0, 0.885), "metal")
    _floor_lines(spec, env, 1.55)
