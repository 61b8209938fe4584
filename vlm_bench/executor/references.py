"""Reference points of ARM-step objects in the live simulation, computed by the GT's own rule.

The ground truth tracks the scene with ideal kinematics; the executor reads the same state from
the simulation (object bottom centres = body origins, drawer openings = slide joints, what the
gripper holds) and asks :meth:`GroundTruthBuilder.step_reference` for the point, so a GT plan
stops exactly where the GT expects and a place approaches the held object's resting point.
"""

from __future__ import annotations

import mujoco

from vlm_bench.episodes.gt_builder import GroundTruthBuilder, Reference
from vlm_bench.sim.constants import part_joint
from vlm_bench.types.episode import Episode

__all__ = ["Reference", "StepReferences"]


class StepReferences:
    """Reference points of one episode's objects, read from a live simulation."""

    def __init__(self, episode: Episode, model: mujoco.MjModel) -> None:
        self.episode = episode
        self.model = model
        self.builder = GroundTruthBuilder(list(episode.objects), list(episode.parts))
        self._joints = {p.id: int(model.joint(part_joint(p.id)).qposadr[0]) for p in episode.parts}

    def __call__(
        self, data: mujoco.MjData, obj_id: str, skill: str, held: str | None = None
    ) -> Reference | None:
        """The reference of ARM step (``skill``, ``obj_id``) now; ``None`` for unknown ids."""
        bottoms = {}
        for o in self.episode.objects:
            x, y, z = (float(v) for v in data.body(o.id).xpos)
            bottoms[o.id] = (x, y, z)
        openings = {part: float(data.qpos[adr]) for part, adr in self._joints.items()}
        return self.builder.step_reference(obj_id, skill, bottoms, openings, held)
