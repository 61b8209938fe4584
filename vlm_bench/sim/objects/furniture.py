"""Static furniture: the table and its height variants (the same build, the kind's height)."""

from __future__ import annotations

import mujoco

from vlm_bench.sim.objects.builder_kit import OBJECT_BUILDERS, PLAIN, object_kit, shade
from vlm_bench.types.base import RGBA
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

TOP_THICKNESS = 0.04


@OBJECT_BUILDERS.register("high_table")
@OBJECT_BUILDERS.register("low_table")
@OBJECT_BUILDERS.register("table")
def build_table(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    rgba: RGBA,
) -> mujoco.MjsBody:
    """A four-legged table (fixed): top, apron and legs; its top surface is at ``size.z``."""
    kit = object_kit(spec, parent, obj, kind, PLAIN)
    lx, ly, h = kind.size
    top = kit.look(rgba)
    frame = kit.look(shade(rgba, 0.8))
    t = TOP_THICKNESS
    kit.box("top", (lx / 2, ly / 2, t / 2), (0.0, 0.0, h - t / 2), top)
    kit.box(
        "edge",
        (lx / 2 + 0.0005, ly / 2 + 0.0005, 0.004),
        (0.0, 0.0, h - t + 0.004),
        frame,
        solid=False,
    )
    leg, inset = 0.05, 0.04
    apron_h = 0.08
    lx_in, ly_in = lx / 2 - inset - leg / 2, ly / 2 - inset - leg / 2
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        pos = (sx * lx_in, sy * ly_in, (h - t) / 2)
        kit.box(f"leg{i}", (leg / 2, leg / 2, (h - t) / 2), pos, frame)
    z = h - t - apron_h / 2
    for name, sign in (("front", 1.0), ("back", -1.0)):
        kit.box(f"apron_{name}", (0.01, ly_in, apron_h / 2), (sign * lx_in, 0.0, z), frame)
    for name, sign in (("left", 1.0), ("right", -1.0)):
        kit.box(f"apron_{name}", (lx_in, 0.01, apron_h / 2), (0.0, sign * ly_in, z), frame)
    return kit.finish(kind.mass)
