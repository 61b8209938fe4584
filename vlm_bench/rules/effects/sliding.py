"""Effect model of pushing an object along its support."""

from __future__ import annotations

from vlm_bench.rules.effects.base import PlanningState, SkillEffect
from vlm_bench.types.plan import ArmStep


class Slide(SkillEffect):
    """``push``: with a target, the object ends halfway to where things placed on the target
    rest (a push stops short of the target); without one, it leaves its support."""

    def apply(self, state: PlanningState, step: ArmStep) -> None:
        if step.target is None:
            state.remove(step.object)
            return
        goal, bottom = state.rest_on(step.target), state.bottom(step.object)
        if goal is None or bottom is None:
            return
        middle = ((bottom[0] + goal[0]) / 2, (bottom[1] + goal[1]) / 2, bottom[2])
        state.set_bottom(step.object, middle)
