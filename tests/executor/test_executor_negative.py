"""Wrong plans fail for the right reason, and grasps are physical (docs/design.md#executor).

All cases perturb the GT plan of ``color_distractor_green`` seed 0 (``right``, pick green_cube,
place yellow_basket), whose GT execution succeeds.
"""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor import ExecutionResult, execute_plan
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.grasping import Picker
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.placing import Placer
from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import arm_qpos, set_arm_targets
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig, FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep, Direction, UavStep

TASK = "color_distractor_green"


@pytest.fixture(scope="module")
def episode() -> Episode:
    return get_episode(TASK, 0)


def _run(episode: Episode, plan: list[UavStep | ArmStep]) -> ExecutionResult:
    return execute_plan(episode, plan)


def test_gt_plan_succeeds(episode: Episode) -> None:
    result = _run(episode, list(episode.gt_plan))
    assert result.exec_success, result.failure_reason
    assert result.goals == (True,)
    assert result.scores is not None and result.scores.s_task == 100.0
    assert result.scores.s_pos == 100.0 and result.scores.s_safe > 99.0


def test_wrong_first_direction_leaves_the_object_out_of_reach(episode: Episode) -> None:
    move, pick, place = episode.gt_plan
    assert isinstance(move, UavStep) and move.direction is Direction.FRONTRIGHT
    result = _run(episode, [UavStep(direction=Direction.BACKLEFT), pick, place])
    assert result.steps[1].status == "failed"
    assert result.failure_reason == "step 1: green_cube is out of reach"
    assert result.failure_code is FailureCode.OUT_OF_REACH
    assert [s.failure_code for s in result.steps] == [
        None,
        FailureCode.OUT_OF_REACH,
        FailureCode.EARLIER_FAILURE,
    ]
    assert result.goals == (False,) and not result.exec_success
    assert result.scores is not None and result.scores.s_pos < 50.0


def test_missing_uav_move_fails_the_pick(episode: Episode) -> None:
    _, pick, place = episode.gt_plan
    result = _run(episode, [pick, place])
    assert result.failure_reason == "step 0: green_cube is out of reach"
    assert [s.status for s in result.steps] == ["failed", "skipped"]
    assert result.goals == (False,)


def test_hallucinated_object_fails_with_unknown_object(episode: Episode) -> None:
    move, _, place = episode.gt_plan
    plan = [move, ArmStep(object="purple_unicorn", skill="pick"), place]
    result = _run(episode, plan)
    assert result.failure_reason == "step 1: unknown object 'purple_unicorn'"
    assert result.failure_code is FailureCode.UNKNOWN_OBJECT
    assert result.steps[1].arm is not None and not result.steps[1].arm.known
    assert result.goals == (False,)


def test_place_before_pick_fails_with_nothing_held(episode: Episode) -> None:
    move, pick, place = episode.gt_plan
    result = _run(episode, [move, place, pick])
    assert result.failure_reason == "step 1: nothing held"
    assert result.failure_code is FailureCode.NOTHING_HELD
    assert result.goals == (False,)


def test_picking_the_distractor_misses_the_goal_and_costs_safety(episode: Episode) -> None:
    move, _, place = episode.gt_plan
    plan = [move, ArmStep(object="gray_cube_1", skill="pick"), place]
    result = _run(episode, plan)
    assert result.steps[1].status == "ok"  # the distractor really is picked up
    assert result.goals == (False,) and not result.exec_success
    assert result.failure_reason is not None
    assert result.displacement["gray_cube_1"] > 0.05  # a non-target object moved
    assert result.scores is not None and result.scores.s_safe < 100.0


def _with_mid_air_release(loop: SimLoop) -> dict[str, Skill]:
    """pick/place plus ``push`` rebound to "open the gripper where you are" (a test probe)."""
    hand = Hand(loop)

    def release(episode: Episode, step: ArmStep) -> SkillFailure | None:
        set_arm_targets(loop.model, loop.data, arm_qpos(loop.model, loop.data), c.GRIPPER_OPEN)
        loop.hold(1.0)
        return None

    return {"pick": Picker(hand).pick, "place": Placer(hand).place, "push": release}


def test_release_mid_air_drops_the_object_and_place_finds_nothing_held(
    episode: Episode,
) -> None:
    move, pick, place = episode.gt_plan
    plan = [move, pick, ArmStep(object="green_cube", skill="push"), place]
    z_table = 0.75
    lifted: list[float] = []

    def watch(loop: SimLoop) -> None:
        lifted.append(float(loop.data.body("green_cube").xpos[2]))

    result = execute_plan(episode, plan, arm_skills=_with_mid_air_release, observers=[watch])
    assert max(lifted) > z_table + 0.08  # it was really lifted by the fingers
    assert result.steps[3].status == "failed"
    assert result.failure_reason == "step 3: green_cube slipped from the gripper"
    final_z = lifted[-1]
    assert final_z < max(lifted) - 0.1  # it fell, onto whatever lay below the hand
    assert not result.exec_success  # even where it happens to fall into the basket
    assert np.isfinite(final_z)


def test_a_users_skill_failure_is_recorded_as_given(episode: Episode) -> None:
    """A user's skill (the :class:`Skill` protocol: the step in, a typed failure out) fails
    its step with its own code and reason, and the code reaches the stored summary."""
    move, pick, _ = episode.gt_plan

    def on_strike(episode: Episode, step: ArmStep) -> SkillFailure | None:
        return SkillFailure(FailureCode.SKILL_FAILED, f"the gripper is on strike ({step.object})")

    def skills(loop: SimLoop) -> dict[str, Skill]:
        return {"pick": on_strike}

    result = execute_plan(episode, [move, pick], arm_skills=skills)
    assert result.failure_reason == f"step 1: the gripper is on strike ({pick.object})"
    assert result.failure_code is FailureCode.SKILL_FAILED
    assert ExecutionSummary.of(result).failure_code is FailureCode.SKILL_FAILED


def test_an_execution_past_its_simulated_time_budget_fails_with_its_code(episode: Episode) -> None:
    config = ExecutorConfig(budget_base_s=1.0, budget_per_step_s=0.5)
    assert config.sim_budget_s(2) == 2.0
    plan = [UavStep(direction=Direction.RIGHT), UavStep(direction=Direction.LEFT)]
    result = execute_plan(episode, plan, config)
    first, second = result.steps
    assert first.failure_code == FailureCode.SIM_BUDGET and first.status == "failed"
    assert second.failure_code == FailureCode.EARLIER_FAILURE
    assert result.failure_code == FailureCode.SIM_BUDGET and not result.exec_success
    assert result.sim_time_s < 2.0 + 0.1 + config.settle_s + 0.1  # cut, then settled
