"""Industrial parts: bolt, nut, camera module, LiDAR."""

from __future__ import annotations

import math

import mujoco

from vlm_bench.sim.objects.builder_kit import (
    GRIP,
    OBJECT_BUILDERS,
    object_kit,
    paint,
    shade,
)
from vlm_bench.sim.objects.frames import axis_angle, quat_mul, yaw
from vlm_bench.sim.objects.meshes import hex_ring, prism
from vlm_bench.sim.objects.textures import textured_look, threads
from vlm_bench.types.base import RGBA
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

GLASS: RGBA = (0.04, 0.06, 0.12, 1.0)
NUT_FLAT_DEG = 45.0  # deg: a nut's first flat's outward normal in its frame (then every 60)
_X_AXIS = axis_angle((0.0, 1.0, 0.0), 90.0)  # turns a cylinder's axis (z) onto +x


@OBJECT_BUILDERS.register("bolt")
def build_bolt(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A hex flange bolt lying on its side, shaft along +x, head at -x, threads drawn."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    lx, dy, dz = kind.size
    steel = paint(spec, rgba, specular=0.7, shininess=0.6)
    r_head = dy / 2  # hexagon corner radius: 2.2 cm across corners, flats up and down
    zc = dz / 2
    x0 = -lx / 2
    head_len, flange_len = 0.008, 0.002
    for i, deg in enumerate((0.0, 60.0, 120.0)):  # three boxes make a hexagonal prism
        quat = quat_mul(axis_angle((1.0, 0.0, 0.0), deg), _X_AXIS)
        # Local z runs along +x. Lengths differ by 0.4 mm: no coplanar overlapping end faces.
        length = head_len - 0.0004 * i
        half = (r_head * math.sqrt(3) / 2, r_head / 2, length / 2)
        kit.box(f"head{i}", half, (x0 + head_len - length / 2, 0.0, zc), steel, quat)
    # A 12-sided flange (apothem dz/2) makes the height and keeps the bolt from rolling.
    apothem = dz / 2
    corner = apothem / math.cos(math.radians(15.0))
    base = (x0 + head_len, 0.0, zc)
    verts = prism(12, corner, corner, flange_len, 15.0, base, along_x=True)
    area = 12 * apothem**2 * math.tan(math.radians(15.0))
    kit.mesh("flange", verts, area * flange_len, steel)
    shaft_r = 0.006
    shank_x0 = x0 + head_len + flange_len
    shank_len = 0.018
    pos = (shank_x0 + shank_len / 2, 0.0, zc)
    kit.cylinder("shank", shaft_r, shank_len / 2, pos, steel, _X_AXIS)
    thread_len = lx / 2 - (shank_x0 + shank_len)
    pos = (lx / 2 - thread_len / 2, 0.0, zc)
    thread = textured_look(spec, threads, rgba, specular=0.6)
    kit.cylinder("thread", shaft_r, thread_len / 2, pos, thread, _X_AXIS)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("nut")
def build_nut(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A hex nut lying flat, turned 15° so its corners fill the square footprint.

    Drawn as a mesh with a bore; six hidden boxes (one per flat) collide.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    width, h = min(kind.size[:2]), kind.size[2]
    corner_r = width / 2 / math.cos(math.radians(15.0))
    hole_r = 0.45 * corner_r
    verts, faces = hex_ring(corner_r, hole_r, h, 15.0)
    look = paint(spec, rgba, specular=0.6, shininess=0.5)
    area = 1.5 * math.sqrt(3) * corner_r**2 - math.pi * hole_r**2
    kit.mesh("body", verts, area * h, look, faces, solid=False)
    apothem = corner_r * math.cos(math.radians(30.0))
    t = apothem - hole_r
    for i in range(6):
        az = NUT_FLAT_DEG + 60.0 * i  # outward normal of each flat (corners at 15° + 60° k)
        r = apothem - t / 2
        pos = (r * math.cos(math.radians(az)), r * math.sin(math.radians(az)), h / 2)
        kit.hide(kit.box(f"side{i}", (t / 2, corner_r / 2, h / 2), pos, look, yaw(az)))
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("camera_module")
def build_camera_module(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A camera: boxy body with a lens barrel toward +x (silver ring, glass) and a red LED."""
    kit = object_kit(spec, parent, obj, kind, GRIP)
    lx, ly, h = kind.size
    lens_len = 0.3 * lx
    bx = lx - lens_len
    housing = paint(spec, rgba, specular=0.3, shininess=0.3)
    kit.box("body", (bx / 2, ly / 2, h / 2), (-lx / 2 + bx / 2, 0.0, h / 2), housing)
    front = -lx / 2 + bx
    lens_r = 0.3 * min(ly, h)
    zc = h / 2
    barrel = paint(spec, (0.13, 0.13, 0.14, 1.0), specular=0.4)
    pos = (front + lens_len / 2, 0.0, zc)
    kit.cylinder("lens", lens_r, lens_len / 2, pos, barrel, _X_AXIS)
    ring = paint(spec, (0.75, 0.76, 0.78, 1.0), specular=0.8, shininess=0.6)
    kit.cylinder(
        "lens_ring", lens_r + 0.0006, 0.0015, (front + 0.0025, 0.0, zc), ring, _X_AXIS, solid=False
    )
    kit.cylinder("lens_rim", lens_r * 0.92, 0.0004, (lx / 2, 0.0, zc), ring, _X_AXIS, solid=False)
    glass = paint(spec, GLASS, specular=1.0, shininess=0.9)
    kit.cylinder(
        "glass", lens_r * 0.7, 0.0005, (lx / 2 + 0.0001, 0.0, zc), glass, _X_AXIS, solid=False
    )
    led = (0.95, 0.1, 0.1, 1.0)
    kit.sphere("led", 0.0018, (front + 0.0002, ly / 2 - 0.007, h - 0.007), led, solid=False)
    kit.box("mount", (0.008, 0.008, 0.0004), (-lx / 2 + bx / 2, 0.0, h), ring, solid=False)
    return kit.finish(kind.mass)


@OBJECT_BUILDERS.register("lidar")
def build_lidar(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A puck LiDAR on a mounting flange: housing, dark glossy window band, top cap with logo.

    The flange is as wide as the kind; the housing above it is 7 cm across, the grasp.
    """
    kit = object_kit(spec, parent, obj, kind, GRIP)
    width, h = min(kind.size[:2]), kind.size[2]
    housing = paint(spec, rgba, specular=0.35, shininess=0.4)
    flange_h = 0.01
    r = min(width / 2 - 0.005, 0.035)
    kit.cylinder("flange", width / 2, flange_h / 2, (0.0, 0.0, flange_h / 2), shade(rgba, 0.8))
    body_h = h - flange_h
    kit.cylinder("housing", r, body_h / 2, (0.0, 0.0, flange_h + body_h / 2), housing)
    window = paint(spec, GLASS, specular=1.0, shininess=0.9)
    band_z = flange_h + 0.45 * body_h
    kit.cylinder("window", r + 0.0005, 0.24 * body_h, (0.0, 0.0, band_z), window, solid=False)
    trim = paint(spec, (0.78, 0.79, 0.8, 1.0), specular=0.7)
    for i, dz in enumerate((-0.245, 0.245)):
        z = band_z + dz * body_h
        kit.cylinder(f"trim{i}", r + 0.0006, 0.0008, (0.0, 0.0, z), trim, solid=False)
    kit.cylinder("logo", 0.4 * r, 0.0003, (0.0, 0.0, h), trim, solid=False)
    return kit.finish(kind.mass)
