"""Reference points of plan objects in the live simulation, mirroring the GT's ``_ref``.

The ground truth (``vlm_bench.episodes.ground_truth``) tracks where each object is with ideal
kinematics; the executor reads the same points from the simulated state: an object's reference
is its bottom centre (the body origin) raised by half its catalogue height, a part's is its
handle site. Both use the same stand-off, so GT plans stop where the GT expects.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from vlm_bench.catalog.world import object_kind
from vlm_bench.sim.constants import part_handle_site
from vlm_bench.types.episode import Episode
from vlm_bench.types.geometry import APPROACH


@dataclass(frozen=True)
class Reference:
    """Where the UAV approaches an object: point (m, world) and horizontal stand-off (m)."""

    x: float
    y: float
    z: float
    standoff: float


def object_reference(
    episode: Episode, model: mujoco.MjModel, data: mujoco.MjData, obj_id: str
) -> Reference | None:
    """Reference of object or part ``obj_id`` now; ``None`` if the episode has no such id."""
    objects = {o.id: o for o in episode.objects}
    parts = {p.id: p for p in episode.parts}
    if obj_id in parts:
        owner = objects[parts[obj_id].parent]
        specs = [p for p in object_kind(owner.kind).parts if p.name == obj_id]
        standoff = specs[0].standoff if specs and specs[0].standoff else None
        x, y, z = (float(v) for v in data.site(part_handle_site(obj_id)).xpos)
        return Reference(x, y, z, standoff or APPROACH.standoff_horizontal)
    if obj_id in objects:
        height = object_kind(objects[obj_id].kind).size[2]
        x, y, z = (float(v) for v in data.body(obj_id).xpos)
        return Reference(x, y, z + height / 2, APPROACH.standoff_horizontal)
    return None
