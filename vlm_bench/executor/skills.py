"""The executor's default ARM skills, bound to one simulation loop."""

from __future__ import annotations

from vlm_bench.executor.grasping import grasp_skills
from vlm_bench.executor.loop import ArmSkill, SimLoop


def default_skills(loop: SimLoop) -> dict[str, ArmSkill]:
    """The scripted skills of SPEC §7 for ``loop`` (they share what the gripper holds)."""
    return {**grasp_skills(loop)}
