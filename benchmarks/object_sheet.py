"""Render a labelled contact sheet of every object kind (default colour) for visual review.

Usage: ``python benchmarks/object_sheet.py [OUT.png] [--tile 224] [--scene] [--color NAME]``

Each tile shows one kind on a neutral floor from a VLM-like 3/4 view (35° down), framed to the
kind's size. ``--scene`` also writes ``OUT_scene.png``: small objects on a table seen from 1.3 m
at 448 px, about what the UAV camera sees. Prints the mean render time per tile.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np
from PIL import Image, ImageDraw

from vlm_bench.catalog.world_catalog import object_kinds
from vlm_bench.sim.objects import add_object
from vlm_bench.sim.objects.builder_kit import shade
from vlm_bench.types.base import Vec3
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

FLOOR = (0.62, 0.62, 0.6, 1.0)
LABEL_H = 22
COLUMNS = 5


def new_spec(size: int, shadows: bool) -> mujoco.MjSpec:
    """An empty scene: grey floor, sun and fill light, offscreen buffer of ``size``."""
    spec = mujoco.MjSpec()
    spec.visual.global_.offwidth = spec.visual.global_.offheight = max(size, 640)
    spec.visual.headlight.ambient = [0.25, 0.25, 0.25]
    spec.visual.headlight.diffuse = [0.35, 0.35, 0.35]
    spec.visual.quality.shadowsize = 2048
    mat = spec.add_material(name="floor")
    mat.rgba = list(FLOOR)
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[6, 6, 0.1], material="floor"
    )
    spec.worldbody.add_light(
        name="sun",
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        dir=[0.3, 0.4, -1.0],
        pos=[0, 0, 4],
        diffuse=[0.65, 0.65, 0.65],
        ambient=[0.2, 0.2, 0.2],
        castshadow=shadows,
    )
    return spec


def look_at(spec: mujoco.MjSpec, name: str, eye: Vec3, target: Vec3, fovy: float = 45.0) -> None:
    """Add a fixed camera at ``eye`` looking at ``target``."""
    f = np.subtract(target, eye)
    f /= np.linalg.norm(f)
    right = np.cross(f, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, f)
    spec.worldbody.add_camera(name=name, pos=list(eye), xyaxes=[*right, *up], fovy=fovy)


def tile(kind: ObjectKind, size: int, color: str | None = None) -> tuple[np.ndarray, float]:
    """Render one kind (no shadows: llvmpipe's shadow acne hides details at this scale).

    Returns the image and the time of a warm render (s).
    """
    spec = new_spec(size, shadows=False)
    obj = EpisodeObject(
        id=kind.name,
        kind=kind.name,
        color=color or kind.default_color or "gray",
        pos=(0.0, 0.0, 0.0),
        yaw_deg=0.0,
        on="floor",
        role="target",
    )
    add_object(spec, obj)
    sx, sy, sz = kind.size
    radius = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
    dist = 1.3 * radius / math.tan(math.radians(22.5))
    az, el = math.radians(35.0), math.radians(32.0)
    target = (0.0, 0.0, sz * 0.45)
    eye = (
        dist * math.cos(el) * math.cos(az),
        dist * math.cos(el) * math.sin(az) * -1.0,
        target[2] + dist * math.sin(el),
    )
    look_at(spec, "view", eye, target)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with mujoco.Renderer(model, size, size) as renderer:
        renderer.update_scene(data, "view")
        renderer.render()  # the first render uploads textures
        start = time.perf_counter()
        renderer.update_scene(data, "view")
        pixels = renderer.render()
        return pixels.copy(), time.perf_counter() - start


def scene(size: int) -> np.ndarray:
    """Small objects on a table, seen from about where the UAV camera would be (with shadows)."""
    spec = new_spec(size, shadows=True)
    small = [k for k in object_kinds().values() if k.graspable and max(k.size) < 0.25]
    items = [("table", (0.0, 0.0, 0.0), 0.0)]
    for i, k in enumerate(small):
        row, col = divmod(i, 5)
        items.append((k.name, (0.27 - 0.17 * row, -0.32 + 0.16 * col, 0.75), 25.0 * i))
    for name, pos, yaw in items:
        kind = object_kinds()[name]
        add_object(
            spec,
            EpisodeObject(
                id=name,
                kind=name,
                color=kind.default_color or "gray",
                pos=pos,
                yaw_deg=yaw,
                on="floor",
                role="target",
            ),
        )
    look_at(spec, "view", (0.95, -0.3, 1.3), (-0.05, 0.0, 0.75), fovy=55.0)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with mujoco.Renderer(model, size, size) as renderer:
        renderer.update_scene(data, "view")
        pixels: np.ndarray = renderer.render().copy()
        return pixels


def main() -> None:
    """Render the sheet (and optionally the table scene) and print timings."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="/tmp/object_sheet.png")
    parser.add_argument("--tile", type=int, default=224, help="tile size in pixels")
    parser.add_argument("--scene", action="store_true", help="also render a table scene")
    parser.add_argument("--color", help="render every kind in this named colour")
    args = parser.parse_args()
    kinds = list(object_kinds().values())
    rows = math.ceil(len(kinds) / COLUMNS)
    t = args.tile
    sheet = Image.new("RGB", (COLUMNS * t, rows * (t + LABEL_H)), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    times = []
    for i, kind in enumerate(kinds):
        pixels, seconds = tile(kind, t, args.color)
        times.append(seconds)
        row, col = divmod(i, COLUMNS)
        x, y = col * t, row * (t + LABEL_H)
        sheet.paste(Image.fromarray(pixels), (x, y))
        label = f"{kind.name} ({args.color or kind.default_color})"
        draw.text(
            (x + 4, y + t + 4), label, fill=tuple(int(255 * c) for c in shade(FLOOR, 0.2)[:3])
        )
    out = Path(args.out)
    sheet.save(out)
    print(f"wrote {out} ({len(kinds)} kinds); render {1000 * np.mean(times):.1f} ms/tile at {t}px")
    if args.scene:
        scene_out = out.with_name(out.stem + "_scene.png")
        Image.fromarray(scene(448)).save(scene_out)
        print(f"wrote {scene_out}")


if __name__ == "__main__":
    main()
