"""The executor's default ARM skills, bound to one simulation loop."""

from __future__ import annotations

from vlm_bench.executor.arm import Arm
from vlm_bench.executor.articulation import articulation_skills
from vlm_bench.executor.grasping import grasp_skills
from vlm_bench.executor.loop import ArmSkill, SimLoop
from vlm_bench.executor.pushing import push_skills


def default_skills(loop: SimLoop) -> dict[str, ArmSkill]:
    """The scripted skills of SPEC §7 for ``loop`` (they share the arm and what it holds)."""
    arm = Arm(loop)
    return {
        **grasp_skills(loop, arm),
        **push_skills(loop, arm),
        **articulation_skills(loop, arm),
    }
