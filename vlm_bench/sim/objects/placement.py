"""Put catalogue objects into a scene and set their parts' initial state."""

from __future__ import annotations

import math

import mujoco

from vlm_bench.catalog.world_catalog import color, object_kind
from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.sim.constants import part_joint
from vlm_bench.sim.objects.builder_kit import OBJECT_BUILDERS
from vlm_bench.types.episode import EpisodeObject


def add_object(spec: mujoco.MjSpec, obj: EpisodeObject) -> mujoco.MjsBody:
    """Build ``obj`` under the world body at ``obj.pos``, turned ``obj.yaw_deg`` about z.

    Args:
        spec: Scene being built.
        obj: The episode object (id, kind, colour, pose).

    Returns:
        The object's body (named ``obj.id``; origin at the bottom centre of its bounding box).

    Raises:
        UnknownNameError: The kind or colour is not in the world catalogue.
    """
    kind = object_kind(obj.kind)
    rgba = color(obj.color)
    return OBJECT_BUILDERS.get(kind.name)(spec, spec.worldbody, obj, kind, rgba)


def apply_initial_state(model: mujoco.MjModel, data: mujoco.MjData, obj: EpisodeObject) -> None:
    """Set the part joints of ``obj`` from ``obj.initial``; call after compiling, before forward.

    ``obj.initial`` maps part names to a drawer opening (m) or a knob angle (deg).

    Raises:
        UnknownNameError: A key is not a part of the object's kind.
        ConfigError: A value lies outside the joint's range.
    """
    parts = {p.name: p for p in object_kind(obj.kind).parts}
    for name, value in obj.initial.items():
        if name not in parts:
            raise UnknownNameError(f"part of {obj.kind}", name, parts)
        joint = model.joint(part_joint(name))
        q = math.radians(value) if parts[name].kind == "knob" else value
        lo, hi = (float(x) for x in joint.range)
        if not lo - 1e-9 <= q <= hi + 1e-9:
            unit = "deg" if parts[name].kind == "knob" else "m"
            shown = (math.degrees(lo), math.degrees(hi)) if unit == "deg" else (lo, hi)
            raise ConfigError(
                f"initial state of {obj.id}.{name} = {value} {unit} is outside "
                f"[{shown[0]:g}, {shown[1]:g}] {unit}"
            )
        data.qpos[model.jnt_qposadr[joint.id]] = q
