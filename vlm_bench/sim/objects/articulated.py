"""Fixtures with moving parts: the drawer cabinet and the stove.

Each part (from ``kind.parts``) is a child body named after the part, on joint
``part_joint(name)``, with a site ``part_handle_site(name)`` exactly at the part's ``handle``
offset when closed / at zero. Part geoms are prefixed by the part name (its id in plans).
A drawer body's origin is the centre of its floor's top surface, so "inside the drawer" is
``|x| < depth/2, |y| < width/2, z > 0`` in the drawer frame.
"""

from __future__ import annotations

import math

import mujoco

from vlm_bench.sim.constants import part_handle_site, part_joint
from vlm_bench.sim.objects.builder_kit import (
    GRIP,
    OBJECT_BUILDERS,
    PLAIN,
    Kit,
    is_light,
    object_kit,
    paint,
    shade,
)
from vlm_bench.sim.objects.containers import WALL, open_box
from vlm_bench.sim.objects.frames import axis_angle
from vlm_bench.types.base import RGBA
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind, PartSpec

METAL: RGBA = (0.72, 0.73, 0.76, 1.0)
DARK: RGBA = (0.07, 0.07, 0.08, 1.0)
DRAWER_TRAVEL = 0.40  # m
DRAWER_MASS = 2.0  # kg
PANEL = 0.018  # carcass panel thickness
FRONT = 0.02  # drawer front thickness
KNOB_RANGE_DEG = 180.0
KNOB_MASS = 0.05
_ALONG_Y = axis_angle((1.0, 0.0, 0.0), 90.0)  # cylinder axis (z) onto y


def _drawer(
    spec: mujoco.MjSpec,
    cabinet: mujoco.MjsBody,
    kind: ObjectKind,
    part: PartSpec,
    half_h: float,
    rgba: RGBA,
) -> None:
    """One drawer: front panel with bar handle, open box behind it, slide joint along +x."""
    depth, width, _ = kind.size
    hx, _, hz = part.handle
    front_x = depth / 2 - FRONT  # carcass front plane; the drawer front lies in front of it
    box_back = -depth / 2 + PANEL + 0.012
    floor_z = hz - half_h + 0.012  # just above the divider below
    box_w = width - 2 * PANEL - 0.008
    box_h = min(0.25, 2 * half_h - 0.08)
    origin = ((box_back + front_x) / 2, 0.0, floor_z + WALL)
    body = cabinet.add_body(name=part.name, pos=list(origin))
    body.add_joint(
        name=part_joint(part.name),
        type=mujoco.mjtJoint.mjJNT_SLIDE,
        axis=[1.0, 0.0, 0.0],
        range=[0.0, DRAWER_TRAVEL],
        damping=15.0,
        frictionloss=1.0,
        armature=0.05,
    )
    kit = Kit(spec, body, part.name, PLAIN)
    ox, _, oz = origin
    depth_in = front_x - box_back
    open_box(
        kit, "box", (depth_in, box_w, box_h), shade(rgba, 0.9), shade(rgba, 0.8), (0.0, 0.0, -WALL)
    )
    front = kit.look(rgba)
    kit.box(
        "front",
        (FRONT / 2, width / 2 - 0.003, half_h),
        (front_x + FRONT / 2 - ox, 0.0, hz - oz),
        front,
    )
    # Handles contrast with the fronts: dark on light cabinets, metal on dark ones.
    metal = paint(spec, (0.16, 0.16, 0.17, 1.0) if is_light(rgba) else METAL, 0.8, 0.6)
    bar_r, span = 0.009, min(0.2, 0.6 * width)
    handle = (hx - ox, 0.0, hz - oz)
    bar = kit.cylinder("handle_bar", bar_r, span / 2, handle, metal, _ALONG_Y)
    bar.friction, bar.condim = list(GRIP.friction), GRIP.condim  # it is grasped to pull
    for i, y in enumerate((span / 2 - 0.012, -(span / 2 - 0.012))):
        a = (front_x + FRONT - ox, y, handle[2])
        kit.rod(f"handle_post{i}", a, (handle[0], y, handle[2]), 0.005, metal, capped=False)
    body.add_site(name=part_handle_site(part.name), pos=list(handle), size=[0.01, 0.0, 0.0])
    kit.finish(DRAWER_MASS)


@OBJECT_BUILDERS.register("drawer_cabinet")
def build_drawer_cabinet(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A fixed cabinet facing +x with one sliding drawer per part, bar handles protruding."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    depth, width, h = kind.size
    carcass = kit.look(shade(rgba, 0.93))
    front_x = depth / 2 - FRONT
    drawers = sorted((p for p in kind.parts if p.kind == "drawer"), key=lambda p: p.handle[2])
    pitch = drawers[1].handle[2] - drawers[0].handle[2] if len(drawers) > 1 else h - 0.06
    base = drawers[0].handle[2] - pitch / 2
    top = drawers[-1].handle[2] + pitch / 2
    back_x = -depth / 2 + PANEL / 2
    kit.box("back", (PANEL / 2, width / 2, top / 2), (back_x, 0.0, top / 2), carcass)
    mid_x, half_d = (-depth / 2 + front_x) / 2, (front_x + depth / 2) / 2
    for name, sign in (("left", 1.0), ("right", -1.0)):
        pos = (mid_x, sign * (width - PANEL) / 2, top / 2)
        kit.box(f"side_{name}", (half_d, PANEL / 2, top / 2), pos, carcass)
    kit.box("top", (depth / 2, width / 2, (h - top) / 2), (0.0, 0.0, (h + top) / 2), carcass)
    kit.box(
        "plinth", (half_d - 0.01, width / 2 - PANEL, base / 2), (mid_x - 0.01, 0.0, base / 2), DARK
    )
    inner_w = width / 2 - PANEL
    for i in range(len(drawers) + 1):  # shelves between drawers, seen as dark seams
        z = base + i * pitch
        kit.box(
            f"shelf{i}",
            (half_d - PANEL / 2, inner_w, 0.01),
            (mid_x + PANEL / 2, 0.0, z),
            shade(rgba, 0.55),
        )
    for part in drawers:
        _drawer(spec, kit.body, kind, part, pitch / 2 - 0.005, rgba)
    return kit.finish(kind.mass - DRAWER_MASS * len(drawers))


def _knob(spec: mujoco.MjSpec, stove: mujoco.MjsBody, part: PartSpec, top_z: float) -> None:
    """A rotary knob on the cooktop: hinge about z, a grippable 3.6 cm cylinder, a pointer."""
    hx, hy, hz = part.handle
    body = stove.add_body(name=part.name, pos=[hx, hy, top_z])
    body.add_joint(
        name=part_joint(part.name),
        type=mujoco.mjtJoint.mjJNT_HINGE,
        axis=[0.0, 0.0, 1.0],
        # MjSpec reads angles in the compiler's unit (degrees unless a scene changed it).
        range=[0.0, KNOB_RANGE_DEG if spec.compiler.degree else math.radians(KNOB_RANGE_DEG)],
        damping=0.02,
        frictionloss=0.03,  # N·m: holds its angle, well below what a grasp can apply
        armature=0.0005,
    )
    kit = Kit(spec, body, part.name, GRIP)
    metal = paint(spec, METAL, specular=0.8, shininess=0.6)
    grip_h = 0.042
    kit.cylinder("skirt", 0.022, 0.002, (0.0, 0.0, 0.002), metal)
    kit.cylinder(
        "grip", 0.018, (grip_h - 0.004) / 2, (0.0, 0.0, 0.004 + (grip_h - 0.004) / 2), metal
    )
    kit.box("ridge", (0.016, 0.0035, 0.003), (0.0, 0.0, grip_h + 0.003), metal)
    pointer = (0.85, 0.1, 0.08, 1.0)
    kit.box("pointer", (0.007, 0.0025, 0.0004), (0.009, 0.0, grip_h + 0.0062), pointer, solid=False)
    body.add_site(
        name=part_handle_site(part.name), pos=[0.0, 0.0, hz - top_z], size=[0.01, 0.0, 0.0]
    )
    kit.finish(KNOB_MASS)


@OBJECT_BUILDERS.register("stove")
def build_stove(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A fixed stove: oven body with glass door and handle, black cooktop with four burner
    rings, and the rotary knob(s) of ``kind.parts`` standing on the top."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    top_z = h - 0.01
    glass = paint(spec, DARK, specular=0.9, shininess=0.8)
    front_x = lx / 2 - 0.02  # the door handle takes the last 2 cm
    cx = (-lx / 2 + front_x) / 2
    kit.box(
        "cabinet",
        ((front_x + lx / 2) / 2, ly / 2, (top_z - 0.01) / 2),
        (cx, 0.0, (top_z - 0.01) / 2),
        rgba,
    )
    kit.box("cooktop", (lx / 2 - 0.01, ly / 2, 0.005), (-0.01, 0.0, top_z - 0.005), glass)
    ring = paint(spec, (0.45, 0.45, 0.47, 1.0), specular=0.5)
    for i, (bx, by) in enumerate(((-0.13, 0.14), (-0.13, -0.14), (0.07, 0.14), (0.07, -0.14))):
        r = 0.075 if i % 2 else 0.06
        kit.cylinder(
            f"burner{i}", r, 0.0008, (bx, by * ly / 0.6, top_z + 0.0008), ring, solid=False
        )
        kit.cylinder(
            f"burner{i}_in",
            r - 0.012,
            0.001,
            (bx, by * ly / 0.6, top_z + 0.001),
            glass,
            solid=False,
        )
        kit.cylinder(
            f"burner{i}_cap", 0.022, 0.0012, (bx, by * ly / 0.6, top_z + 0.0012), ring, solid=False
        )
    door = kit.look(shade(rgba, 0.97))
    kit.box("door", (0.002, ly / 2 - 0.03, 0.25), (front_x + 0.002, 0.0, 0.37), door, solid=False)
    kit.box(
        "window", (0.0005, ly / 2 - 0.11, 0.13), (front_x + 0.0045, 0.0, 0.38), glass, solid=False
    )
    kit.box(
        "panel",
        (0.002, ly / 2 - 0.005, 0.04),
        (front_x + 0.002, 0.0, top_z - 0.055),
        glass,
        solid=False,
    )
    kit.box(
        "display",
        (0.0005, 0.035, 0.012),
        (front_x + 0.0045, 0.0, top_z - 0.055),
        (0.1, 0.75, 0.3, 1.0),
        solid=False,
    )
    kit.box(
        "kick", (0.002, ly / 2 - 0.005, 0.035), (front_x + 0.002, 0.0, 0.04), glass, solid=False
    )
    metal = paint(spec, METAL, specular=0.8, shininess=0.6)
    kit.cylinder("door_handle", 0.009, 0.2, (lx / 2 - 0.009, 0.0, 0.58), metal, _ALONG_Y)
    for i, y in enumerate((0.18, -0.18)):
        kit.rod(
            f"door_post{i}",
            (front_x, y, 0.58),
            (lx / 2 - 0.009, y, 0.58),
            0.005,
            metal,
            capped=False,
        )
    mark = (0.95, 0.95, 0.95, 1.0)
    for part in kind.parts:
        if part.kind == "knob":
            _knob(spec, kit.body, part, top_z)
            for deg in (0.0, 90.0, 180.0):  # dial marks: where the pointer is at 0°, 90°, 180°
                a = math.radians(deg)
                pos = (
                    part.handle[0] + 0.029 * math.cos(a),
                    part.handle[1] + 0.029 * math.sin(a),
                    top_z + 0.0003,
                )
                kit.box(
                    f"{part.name}_mark{int(deg)}",
                    (0.004, 0.0012, 0.0003),
                    pos,
                    mark,
                    axis_angle((0, 0, 1), deg),
                    solid=False,
                )
    return kit.finish(kind.mass - KNOB_MASS)
