"""The executor's default ARM skills, bound to one simulation loop."""

from __future__ import annotations

from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.articulation import articulation_skills
from vlm_bench.executor.skills.grasping import grasp_skills
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.pushing import push_skills


def default_skills(loop: SimLoop) -> dict[str, Skill]:
    """The scripted skills (docs/design.md#arm-skills) for ``loop`` (they share one hand and
    what it holds)."""
    hand = Hand(loop)
    return {
        **grasp_skills(loop, hand),
        **push_skills(loop, hand),
        **articulation_skills(loop, hand),
    }
