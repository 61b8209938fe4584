"""What is left to do after a failed round, read the way a perfect planner reads its feedback.

The GT's ARM steps are matched in order against the ARM steps executed with success so far;
the rest is still to do, with two corrections a planner reading the state makes: a step that
acts on the held object (``place``) right after its done grasp (``pick``), with nothing held
any more (it slipped), is done again from the grasp; and where every step is done but the task
is not complete, the steps from the last grasp are done again. Which skills grasp and which act
on the held object, each skill's effect model says (:mod:`vlm_bench.rules.effects`).
"""

from __future__ import annotations

from collections.abc import Sequence

from vlm_bench.rules.effects import effect_of
from vlm_bench.types.plan import ArmStep, PlanStep


def remaining_arm_steps(
    arm_steps: Sequence[ArmStep], done: Sequence[PlanStep], held: str | None
) -> tuple[int, list[ArmStep]]:
    """The index in ``arm_steps`` to resume from and the ARM steps still to do (module doc)."""
    k = 0
    for step in done:
        if isinstance(step, ArmStep) and k < len(arm_steps) and step == arm_steps[k]:
            k += 1
    if k == len(arm_steps):
        grasps = [i for i, s in enumerate(arm_steps) if effect_of(s.skill).grasps]
        k = grasps[-1] if grasps else max(0, len(arm_steps) - 1)
    elif (
        held is None
        and k > 0
        and effect_of(arm_steps[k - 1].skill).grasps
        and effect_of(arm_steps[k].skill).needs_held
    ):
        k -= 1
    return k, list(arm_steps[k:])
