"""Toys and blocks: cube, Rubik's cube, teddy bear, wooden block."""

from __future__ import annotations

import mujoco

from vlm_bench.sim.objects.builder_kit import (
    GRIP,
    OBJECT_BUILDERS,
    mix,
    object_kit,
)
from vlm_bench.sim.objects.frames import axis_angle
from vlm_bench.sim.objects.textures import sticker_face, textured_look, wood_grain
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

# Standard Rubik's scheme: white/yellow, green/blue and red/orange on opposite faces.
# Each face: name, colour, outward normal, and the turn (axis, deg) taking +z onto it.
_X, _Y = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
_RUBIK_FACES: tuple[tuple[str, RGBA, Vec3, Vec3, float], ...] = (
    ("top", (0.95, 0.95, 0.95, 1.0), (0.0, 0.0, 1.0), _X, 0.0),
    ("bottom", (0.98, 0.82, 0.05, 1.0), (0.0, 0.0, -1.0), _X, 180.0),
    ("front", (0.05, 0.62, 0.25, 1.0), (1.0, 0.0, 0.0), _Y, 90.0),
    ("back", (0.08, 0.3, 0.85, 1.0), (-1.0, 0.0, 0.0), _Y, -90.0),
    ("left", (0.85, 0.1, 0.1, 1.0), (0.0, 1.0, 0.0), _X, -90.0),
    ("right", (1.0, 0.45, 0.05, 1.0), (0.0, -1.0, 0.0), _X, 90.0),
)


@OBJECT_BUILDERS.register("cube")
def build_cube(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A solid block of one colour."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    kit.box("body", (sx / 2, sy / 2, sz / 2), (0.0, 0.0, sz / 2), kit.look(rgba))
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("rubiks_cube")
def build_rubiks_cube(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A black cube whose six faces carry 3 × 3 stickers in the standard colours."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    edge = min(kind.size)
    half = edge / 2 - 0.0006
    kit.box("body", (half, half, half), (0.0, 0.0, edge / 2), rgba)
    for name, colour, normal, axis, deg in _RUBIK_FACES:
        # A thin plate turned onto its face; its texture draws the 3 × 3 sticker grid.
        off = half + 0.0003
        pos = (normal[0] * off, normal[1] * off, edge / 2 + normal[2] * off)
        look = textured_look(spec, sticker_face, colour, specular=0.3)
        quat = axis_angle(axis, deg)
        kit.box(f"stickers_{name}", (half, half, 0.0003), pos, look, quat, solid=False)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("wood_block")
def build_wood_block(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A wooden bar with a grain texture."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    sx, sy, sz = kind.size
    look = textured_look(spec, wood_grain, rgba, specular=0.1)
    kit.box("body", (sx / 2, sy / 2, sz / 2), (0.0, 0.0, sz / 2), look)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("teddy_bear")
def build_teddy_bear(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A bear sitting upright facing +x: legs forward, arms at its sides, grasped by the head."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    fur = kit.look(rgba)
    pale = kit.look(mix(rgba, (0.95, 0.85, 0.7, 1.0), 0.55))
    dark = kit.look((0.05, 0.04, 0.04, 1.0))
    # Scale a 0.17 m tall layout to the kind's height (keeps proportions for other sizes).
    k = kind.size[2] / 0.17
    for side, y in (("left", 1.0), ("right", -1.0)):
        kit.rod(
            f"leg_{side}",
            (-0.015 * k, 0.03 * k * y, 0.02 * k),
            (0.035 * k, 0.036 * k * y, 0.02 * k),
            0.02 * k,
            fur,
        )
        kit.ellipsoid(
            f"sole_{side}",
            (0.004 * k, 0.014 * k, 0.014 * k),
            (0.053 * k, 0.036 * k * y, 0.021 * k),
            pale,
            solid=False,
        )
        kit.rod(
            f"arm_{side}",
            (-0.012 * k, 0.04 * k * y, 0.095 * k),
            (0.018 * k, 0.054 * k * y, 0.055 * k),
            0.015 * k,
            fur,
        )
        kit.sphere(f"ear_{side}", 0.013 * k, (-0.012 * k, 0.027 * k * y, 0.153 * k), fur)
        kit.sphere(
            f"ear_inner_{side}",
            0.008 * k,
            (-0.004 * k, 0.028 * k * y, 0.155 * k),
            pale,
            solid=False,
        )
        kit.sphere(
            f"eye_{side}", 0.0045 * k, (0.021 * k, 0.013 * k * y, 0.133 * k), dark, solid=False
        )
    kit.ellipsoid("torso", (0.043 * k, 0.048 * k, 0.055 * k), (-0.015 * k, 0.0, 0.062 * k), fur)
    kit.ellipsoid(
        "belly", (0.01 * k, 0.03 * k, 0.035 * k), (0.021 * k, 0.0, 0.058 * k), pale, solid=False
    )
    kit.sphere("head", 0.034 * k, (-0.008 * k, 0.0, 0.125 * k), fur)
    kit.sphere("muzzle", 0.015 * k, (0.018 * k, 0.0, 0.113 * k), pale)
    kit.ellipsoid(
        "nose", (0.005 * k, 0.007 * k, 0.005 * k), (0.032 * k, 0.0, 0.118 * k), dark, solid=False
    )
    return kit.finish(kind.mass)
