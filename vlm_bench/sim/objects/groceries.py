"""Groceries and packages: banana, meat can, tomato can, cleanser, chocolate box, cardboard box."""

from __future__ import annotations

import mujoco

from vlm_bench.sim.objects.builder_kit import (
    GRIP,
    OBJECT_BUILDERS,
    Kit,
    Look,
    is_light,
    object_kit,
    paint,
    shade,
)
from vlm_bench.sim.objects.meshes import tube
from vlm_bench.sim.objects.textures import (
    GOLD,
    INK,
    WHITE,
    bottle_label,
    cardboard,
    shipping_label,
    soup_label,
    textured_look,
    tin_label,
)
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

METAL: RGBA = (0.72, 0.73, 0.76, 1.0)
TAPE: RGBA = (0.78, 0.62, 0.38, 1.0)
CLEANSER_NECK = 0.035  # m from a cleanser's shoulder to its cap
CLEANSER_CAP_R = 0.018  # m


def rounded_slab(
    kit: Kit,
    piece: str,
    lx: float,
    ly: float,
    radius: float,
    z0: float,
    z1: float,
    look: Look,
    solid: bool = True,
) -> None:
    """A prism with a rounded-rectangle footprint ``lx`` × ``ly``, from ``z0`` to ``z1``.

    Two crossed boxes collide; the rounded corners are drawn only (cheaper contacts). The
    overlapping pieces end 0.5 mm apart at the top: coplanar overlapping faces make
    shadow-map acne.
    """
    hx, hy = lx / 2, ly / 2
    for i, (name, half_x, half_y) in enumerate((("x", hx, hy - radius), ("y", hx - radius, hy))):
        top = z1 - 0.0005 * i
        half = (half_x, half_y, (top - z0) / 2)
        kit.box(f"{piece}_{name}", half, (0.0, 0.0, (z0 + top) / 2), look, solid=solid)
    top = z1 - 0.001
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        pos = (sx * (hx - radius), sy * (hy - radius), (z0 + top) / 2)
        kit.cylinder(f"{piece}_corner{i}", radius, (top - z0) / 2, pos, look, solid=False)


def _banana_axis(length: float, width: float, height: float) -> list[tuple[Vec3, float]]:
    """Points (centre, radius) along a banana's curved, tapering axis; each ring touches z=0.

    The arc is a parabola in the ground plane, centred in x and y (its end caps included).
    """
    r_max, n = height / 2, 16
    span, sag = length / 2 - 0.014, width - 1.45 * r_max
    ts = [-1.0 + 2.0 * i / n for i in range(n + 1)]
    rings = [((span * t, sag * (1.0 - t * t)), r_max * (1.0 - 0.55 * t * t)) for t in ts]
    lo_y = min(y - r for (_, y), r in rings)
    hi_y = max(y + r for (_, y), r in rings)
    dy = (lo_y + hi_y) / 2
    return [((x, y - dy, r), r) for (x, y), r in rings]


@OBJECT_BUILDERS.register("banana")
def build_banana(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A banana lying on its side: a smooth curved tapering tube with a stem and a dark tip.

    Hidden capsules along the axis collide; each touches the ground, so it lies flat.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    rings = _banana_axis(*kind.size)
    verts, faces = tube(rings)
    kit.mesh("skin", verts, 1e-6, rgba, faces, solid=False)
    for i in range(0, len(rings) - 2, 2):
        (a, ra), (b, rb) = rings[i], rings[i + 2]
        r = min(ra, rb)
        kit.hide(kit.rod(f"collider{i // 2}", (a[0], a[1], r), (b[0], b[1], r), r, rgba))
    (x0, y0, _), r0 = rings[0]
    (x1, y1, _), r1 = rings[-1]
    stem_end = (x0 - 0.011, y0 - 0.004, r0 + 0.004)
    kit.rod("stem", (x0 + 0.004, y0, r0), stem_end, 0.0052, (0.42, 0.36, 0.14, 1.0))
    dark = (0.22, 0.15, 0.06, 1.0)
    kit.sphere("stem_end", 0.0055, stem_end, dark, solid=False)
    kit.rod("tip", (x1 - 0.004, y1, r1), (x1 + 0.006, y1 - 0.003, r1), 0.0055, dark)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("meat_can")
def build_meat_can(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A rounded-rectangle tin: labelled sides, metal lid and base rim."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    metal = kit.look(METAL)
    label = textured_look(spec, tin_label, rgba)
    rounded_slab(kit, "base", sx - 0.002, sy - 0.002, 0.012, 0.0, 0.006, metal)
    rounded_slab(kit, "label", sx, sy, 0.013, 0.006, sz - 0.008, label)
    rounded_slab(kit, "lid", sx - 0.002, sy - 0.002, 0.012, sz - 0.008, sz, metal)
    kit.box("key", (0.004, 0.012, 0.0008), (0.0, 0.0, sz + 0.0004), shade(METAL, 0.8), solid=False)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("tomato_can")
def build_tomato_can(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A soup can: label in the colour over white with a gold band, metal rims."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    radius, sz = min(kind.size[:2]) / 2, kind.size[2]
    metal = kit.look(METAL)
    kit.cylinder("base", radius - 0.001, 0.003, (0.0, 0.0, 0.003), metal)
    label = textured_look(spec, soup_label, rgba)
    kit.cylinder("label", radius, (sz - 0.012) / 2, (0.0, 0.0, sz / 2), label)
    kit.cylinder("lid", radius - 0.001, 0.003, (0.0, 0.0, sz - 0.003), metal)
    kit.cylinder(
        "lid_ring", radius - 0.006, 0.0004, (0.0, 0.0, sz), shade(METAL, 0.85), solid=False
    )
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("cleanser")
def build_cleanser(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A tall bottle: rounded body, shoulder, neck, cap with nozzle, white front/back labels.

    A top-down hand reaches only ~4 cm down the bottle before its palm meets the cap, so it
    holds the bottle by the cap: 3.6 cm across and (at 0.21 m) 2.8 cm tall.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    plastic = kit.look(rgba)
    cap = kit.look((0.1, 0.3, 0.8, 1.0) if is_light(rgba) else WHITE)
    shoulder_z = sz * 0.7
    rounded_slab(kit, "body", sx, sy, 0.02, 0.0, shoulder_z, plastic)
    kit.ellipsoid(
        "shoulder", (sx / 2 - 0.001, sy / 2 - 0.001, 0.03), (0.0, 0.0, shoulder_z), plastic
    )
    kit.cylinder("neck", 0.013, 0.008, (0.0, 0.0, shoulder_z + 0.03), plastic)
    cap_h = sz - (shoulder_z + CLEANSER_NECK)  # the grasp: the pads' 2.6 cm fit on the cap
    kit.cylinder("cap", CLEANSER_CAP_R, cap_h / 2, (0.0, 0.0, sz - cap_h / 2), cap)
    kit.box("nozzle", (0.008, 0.004, 0.004), (0.02, 0.0, sz - 0.006), cap)
    label = textured_look(spec, bottle_label, rgba)
    for side in (1.0, -1.0):
        kit.box(
            f"label_{'front' if side > 0 else 'back'}",
            (0.0006, sy / 2 - 0.012, shoulder_z * 0.36),
            (side * (sx / 2 + 0.0003), 0.0, shoulder_z * 0.48),
            label,
            solid=False,
        )
    return kit.finish(kind.mass)


def _carton_body(kit: Kit, size: Vec3, look: Look) -> None:
    """The solid body of a closed carton, 1 mm inside the sides and top of ``size``, so that
    bands, seams, tape and labels on its faces stand proud of it."""
    sx, sy, sz = size
    kit.box(
        "body", (sx / 2 - 0.001, sy / 2 - 0.001, sz / 2 - 0.0005), (0.0, 0.0, sz / 2 - 0.0005), look
    )


@OBJECT_BUILDERS.register("chocolate_box")
def build_chocolate_box(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A flat box with a lid seam, a shiny gold band around it and a gold label on top."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    gold = paint(spec, GOLD, specular=0.8, shininess=0.7)
    _carton_body(kit, kind.size, rgba)
    kit.box("band", (0.012, sy / 2, sz / 2), (-0.035, 0.0, sz / 2), gold, solid=False)
    kit.box("seal", (0.02, 0.014, 0.0006), (0.03, 0.0, sz), gold, solid=False)
    kit.box(
        "seam",
        (sx / 2, sy / 2 - 0.0002, 0.0008),
        (0.0, 0.0, sz * 0.7),
        shade(rgba, 0.55),
        solid=False,
    )
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("box")
def build_box(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A closed cardboard box in the given colour, taped shut, with a shipping label."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    board = textured_look(spec, cardboard, rgba, specular=0.05)
    _carton_body(kit, kind.size, board)
    tape = kit.look(TAPE if is_light(rgba) else shade(TAPE, 1.2))
    # Tape across the top along y and down both short ends.
    kit.box("tape_top", (0.011, sy / 2, 0.0005), (0.0, 0.0, sz), tape, solid=False)
    for side in (1.0, -1.0):
        pos = (0.0, side * sy / 2, sz - 0.02)
        kit.box(f"tape_end{int(side)}", (0.011, 0.0005, 0.02), pos, tape, solid=False)
    label = textured_look(spec, shipping_label, INK)
    kit.box("label", (0.0005, 0.028, 0.018), (sx / 2, 0.008, sz * 0.45), label, solid=False)
    return kit.finish(kind.mass)
