"""The round machine: a round's typed outcome in, the next action out; the step budget, the end
rules, the feedback and the steps executed, with no simulator."""

from __future__ import annotations

from vlm_bench.rounds import Done, Execute, Replan, RoundMachine
from vlm_bench.types.closed_loop import LoopConfig
from vlm_bench.types.execution import ExecutionSummary, FailureCode
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.rounds import RoundOutcome, StepFailure

UP = UavStep(direction=Direction.UP, distance=0.5)
PICK = ArmStep(object="cube", skill="pick")
PLACE = ArmStep(object="cube", skill="place", target="table")


def _outcome(done: int, failed: StepFailure | None = None, ok: bool = False) -> RoundOutcome:
    summary = ExecutionSummary(
        exec_success=ok,
        steps_ok=failed is None,
        n_steps_done=done,
        s_task=100.0 if ok else 0.0,
        sim_time_s=1.0,
        wall_time_s=0.0,
        failure_reason=None if ok or failed is None else f"step {failed.index}: {failed.detail}",
        failure_code=None if ok else (failed.code if failed else FailureCode.GOAL_NOT_MET),
    )
    return RoundOutcome(execution=summary, failed_step=failed, held="cube" if done > 1 else None)


def test_an_open_loop_is_one_round_whatever_its_outcome() -> None:
    machine = RoundMachine()
    assert machine.start([UP, PICK]) == Execute(0, (UP, PICK))
    done = machine.executed_round(
        _outcome(1, StepFailure(index=1, code=FailureCode.GRASP_FAILED, detail="x"))
    )
    assert isinstance(done, Done) and done.end == "max_rounds"
    assert done.outcome.succ_at == (False,) and done.outcome.rounds_used == 1


def test_a_failed_round_asks_for_a_replan_with_typed_feedback() -> None:
    machine = RoundMachine.closed(LoopConfig(max_rounds=2), gt_steps=3)
    machine.start([UP, PICK, PLACE])
    failure = StepFailure(index=2, code=FailureCode.SLIPPED, detail="step 9: text as it is")
    replan = machine.executed_round(_outcome(2, failure))
    assert isinstance(replan, Replan) and replan.round == 1
    executed = replan.feedback.executed
    assert [s.status for s in executed] == ["done", "done", "failed"]
    # the detail is the executor's, as typed: nothing is cut from it
    assert executed[2].code == "slipped" and executed[2].detail == "step 9: text as it is"
    assert replan.feedback.held == "cube" and not replan.feedback.incomplete
    execute = machine.answered([PICK, PLACE])
    assert execute == Execute(1, (PICK, PLACE))
    done = machine.executed_round(_outcome(2, ok=True))
    assert isinstance(done, Done) and done.end == "success"
    assert done.outcome.succ_at == (False, True, True) and done.outcome.recovered
    assert done.outcome.steps_executed == 5 and done.outcome.failure_codes == ("slipped", None)


def test_the_step_budget_cuts_a_replan_and_ends_the_episode() -> None:
    machine = RoundMachine.closed(LoopConfig(max_rounds=5, step_budget=4), gt_steps=3)
    machine.start([UP, UP, UP])  # round 0 is never cut
    machine.executed_round(_outcome(3))  # every step ran, goals unmet
    execute = machine.answered([UP, UP, UP])
    assert isinstance(execute, Execute) and execute.steps == (UP,) and execute.truncated == 2
    done = machine.executed_round(_outcome(1))
    assert isinstance(done, Done) and done.end == "budget" and done.outcome.steps_executed == 4


def test_no_plan_and_a_crash_end_the_episode() -> None:
    assert RoundMachine.closed(LoopConfig(), 2).start(None).outcome.end == "no_plan"  # type: ignore[union-attr]
    machine = RoundMachine.closed(LoopConfig(), 2)
    machine.start([UP])
    machine.executed_round(_outcome(1))
    done = machine.answered([])
    assert isinstance(done, Done) and done.end == "no_plan"
    assert done.outcome.failure_codes == ("goal_not_met", "no_plan")
    crashing = RoundMachine.closed(LoopConfig(), 2)
    crashing.start([UP])
    crashed = _outcome(0, StepFailure(index=0, code=FailureCode.EXECUTOR_CRASH, detail="bug"))
    end = crashing.executed_round(crashed.model_copy(update={"crashed": True}))
    assert isinstance(end, Done) and end.end == "executor_crash" and crashing.executed == []
