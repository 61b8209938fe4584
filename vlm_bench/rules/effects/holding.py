"""Effect models of taking an object into the gripper and putting it down."""

from __future__ import annotations

from vlm_bench.rules.approach import WorkPoint
from vlm_bench.rules.effects.base import PlanningState, SkillEffect
from vlm_bench.types.plan import ArmStep


class Hold(SkillEffect):
    """``pick``: the gripper holds the step's object, which travels with it."""

    grasps = True

    def apply(self, state: PlanningState, step: ArmStep) -> None:
        state.hold(step.object)


class Release(SkillEffect):
    """``place``: the held object comes to rest on or in the step's object. The step works where
    the held object's centre will be, not at the destination's centre."""

    needs_held = True

    def work_point(self, state: PlanningState, step: ArmStep) -> WorkPoint | None:
        point = state.reference(step.object)
        held = state.held
        if point is None or held is None:
            return point
        rest, tall = state.rest_on(step.object), state.height(held)
        if rest is None or tall is None:
            return point
        return WorkPoint(rest[0], rest[1], rest[2] + tall / 2, point.standoff)

    def apply(self, state: PlanningState, step: ArmStep) -> None:
        held = state.held
        rest = state.rest_on(step.object)
        if held is None or rest is None:  # nothing to put down, or nowhere to put it
            return
        state.set_bottom(held, rest)
        state.hold(None)
