"""Tableware: plate, bowl, mug, cup."""

from __future__ import annotations

import math

import mujoco

from vlm_bench.sim.objects.builder_kit import (
    GRIP,
    OBJECT_BUILDERS,
    PLAIN,
    Kit,
    Look,
    is_light,
    mix,
    object_kit,
    shade,
)
from vlm_bench.sim.objects.frames import axis_angle, quat_mul, yaw
from vlm_bench.sim.objects.meshes import prism
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

WHITE: RGBA = (1.0, 1.0, 1.0, 1.0)
MUG_WALL = 0.005  # m
CUP_RIBS = 24  # capsules round a cup's wall, overlapping
CUP_RIB_R = 0.005  # m
CUP_FLOOR = 0.006  # m


def tilted_ring(
    kit: Kit,
    piece: str,
    inner: tuple[float, float],
    outer: tuple[float, float],
    thickness: float,
    count: int,
    look: Look,
    axis: tuple[float, float] = (0.0, 0.0),
) -> list[mujoco.MjsGeom]:
    """A surface of revolution's band from ``inner`` (r, z) to ``outer`` (r, z) about the
    vertical through ``axis`` (x, y), in box segments.

    The segments' mid-surface follows the band; neighbours overlap so nothing falls through.
    """
    (r0, z0), (r1, z1) = inner, outer
    tilt = math.degrees(math.atan2(r1 - r0, z1 - z0))  # from vertical, leaning outward
    half_len = math.hypot(r1 - r0, z1 - z0) / 2
    half_w = max(r0, r1) * math.tan(math.pi / count) + 0.001
    rm, zm = (r0 + r1) / 2, (z0 + z1) / 2
    out = []
    for i in range(count):
        az = 360.0 * i / count
        c, s = math.cos(math.radians(az)), math.sin(math.radians(az))
        quat = quat_mul(yaw(az), axis_angle((0.0, 1.0, 0.0), tilt))
        half = (thickness / 2, half_w, half_len)
        out.append(
            kit.box(f"{piece}{i}", half, (axis[0] + rm * c, axis[1] + rm * s, zm), look, quat)
        )
    return out


@OBJECT_BUILDERS.register("plate")
def build_plate(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A round plate: foot ring, flat well and a raised rim with a thin coloured band."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    radius, h = min(kind.size[:2]) / 2, kind.size[2]
    glaze = kit.look(rgba)
    kit.cylinder("foot", 0.5 * radius, 0.0015, (0.0, 0.0, 0.0015), shade(rgba, 0.92))
    well_r = 0.72 * radius
    kit.cylinder("well", well_r, 0.0035, (0.0, 0.0, 0.0055), glaze)
    t = 0.006
    tilted_ring(
        kit, "rim", (well_r - 0.003, 0.006), (radius - 0.0045, h - t / 2 - 0.0005), t, 20, glaze
    )
    band = (0.2, 0.35, 0.7, 1.0) if is_light(rgba) else WHITE
    kit.cylinder("band", well_r + 0.001, 0.0002, (0.0, 0.0, 0.0091), band, solid=False)
    kit.cylinder("well_top", well_r - 0.004, 0.0002, (0.0, 0.0, 0.0095), glaze, solid=False)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("bowl")
def build_bowl(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A round bowl: foot, thick floor and a curved wall in two tiers of tilted segments.

    Grasped by the rim (the wall is 1 cm thick), it holds a small cube.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    radius, h = min(kind.size[:2]) / 2, kind.size[2]
    glaze = kit.look(rgba)
    t = 0.01
    kit.cylinder("foot", 0.44 * radius, 0.003, (0.0, 0.0, 0.003), shade(rgba, 0.9))
    floor_r = 0.6 * radius
    kit.cylinder("floor", floor_r, t / 2, (0.0, 0.0, 0.004 + t / 2), glaze)
    knee = (0.84 * radius, 0.5 * h)
    tilted_ring(kit, "wall_low", (floor_r - 0.004, 0.01), knee, t, 16, glaze)
    tilted_ring(kit, "wall_high", knee, (radius - t / 2 - 0.002, h - 0.003), t, 16, glaze)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("mug")
def build_mug(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A cylindrical mug with a handle toward +x and a dark opening.

    The cup is hollow where it collides (a 5 mm wall of segments and the foot as its floor),
    so a gripper can hold it by the rim, one finger inside; it is drawn as a plain cylinder.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    lx, ly, h = kind.size
    foot_r = ly / 2
    body_r = min(foot_r - 0.004, 0.036)
    c = -lx / 2 + foot_r  # cup axis; the handle fills the rest of the length
    glaze = kit.look(rgba)
    kit.cylinder("foot", foot_r, 0.003, (c, 0.0, 0.003), glaze)
    kit.cylinder(
        "body", body_r, (h - 0.004) / 2, (c, 0.0, 0.004 + (h - 0.004) / 2), glaze, solid=False
    )
    wall = (body_r - MUG_WALL / 2, 0.006), (body_r - MUG_WALL / 2, h)
    for seg in tilted_ring(kit, "wall", *wall, MUG_WALL, 16, glaze, axis=(c, 0.0)):
        kit.hide(seg)
    inside = shade(rgba, 0.35)
    kit.cylinder("opening", body_r - 0.005, 0.0003, (c, 0.0, h), inside, solid=False)
    r, x = 0.0065, lx / 2 - 0.0065
    top, bottom = (x, 0.0, 0.78 * h), (x, 0.0, 0.34 * h)
    kit.rod("handle_top", (c + body_r - 0.004, 0.0, 0.8 * h), top, r, glaze)
    kit.rod("handle_side", top, bottom, r, glaze)
    kit.rod("handle_bottom", bottom, (c + body_r - 0.004, 0.0, 0.3 * h), r, glaze)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("cup")
def build_cup(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A tapered cup without a handle: a frustum with ridges and a pale opening.

    The frustum is a drawn mesh; what collides is hidden: a floor and a ring of overlapping
    capsules along the frustum's slant, their outer envelope the frustum. Fingers closing
    across the cup press on round ribs, whose contacts with a pad MuJoCo computes exactly
    wherever the cup slides across it (a pad's edge on a cylinder can get a normal along the
    pad's width: docs/decisions.md).
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    r_top, h = min(kind.size[:2]) / 2, kind.size[2]
    r_bot = 0.72 * r_top
    verts = prism(28, r_bot, r_top, h)
    volume = math.pi * h / 3 * (r_top**2 + r_top * r_bot + r_bot**2)
    kit.mesh("shell", verts, volume, rgba, solid=False)
    rib = CUP_RIB_R
    kit.hide(kit.cylinder("floor", r_bot - rib, CUP_FLOOR / 2, (0.0, 0.0, CUP_FLOOR / 2), rgba))

    def rib_axis(z: float, az: float) -> Vec3:  # a rib's axis lies its radius inside the slant
        r = r_bot + (r_top - r_bot) * z / h - rib
        return (r * math.cos(az), r * math.sin(az), z)

    for i in range(CUP_RIBS):
        az = 2 * math.pi * i / CUP_RIBS
        kit.hide(kit.rod(f"rib{i}", rib_axis(rib, az), rib_axis(h - rib, az), rib, rgba))
    for i, frac in enumerate((0.12, 0.3)):
        r = r_bot + (r_top - r_bot) * frac + 0.0006
        kit.cylinder(f"ridge{i}", r, 0.0012, (0.0, 0.0, h * frac), shade(rgba, 0.8), solid=False)
    inside = shade(rgba, 0.7) if is_light(rgba) else mix(rgba, WHITE, 0.8)
    kit.cylinder("opening", r_top - 0.003, 0.0003, (0.0, 0.0, h), inside, solid=False)
    return kit.finish(kind.mass)
