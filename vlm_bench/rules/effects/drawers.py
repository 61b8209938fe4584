"""Effect model of opening and closing a drawer."""

from __future__ import annotations

from vlm_bench.rules.effects.base import PlanningState, SkillEffect
from vlm_bench.types.plan import ArmStep


class SetOpening(SkillEffect):
    """``pull`` / ``close``: the step's drawer ends ``opening`` m open."""

    def __init__(self, opening: float) -> None:
        self.opening = opening

    def apply(self, state: PlanningState, step: ArmStep) -> None:
        if state.is_drawer(step.object):
            state.set_opening(step.object, self.opening)
