"""The round machine of one episode (docs/closed-loop.md): a round's outcome in, the next action
out.

Round 0 executes the first plan; after a round that fails, the machine asks for a replan, whose
steps execute from where the failed round left the scene, until the task succeeds, ``max_replans``
replans were used, the step budget is spent, an answer holds no plan, or the executor raised. An
open loop is the machine with no replans: its one round is the whole episode.

The machine is pure (no simulator, no model, no pool): whoever drives it (the runner's pool, the
synchronous :func:`~vlm_bench.rounds.drive.drive_episode`, a harness's solver) executes each
:class:`Execute` and answers each :class:`Replan`. It owns the step budget, the end rules, the
feedback a replan gets and the list of steps executed, built from each round's typed
:class:`~vlm_bench.types.rounds.RoundOutcome`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from vlm_bench.types.closed_loop import ExecutedStep, Feedback, LoopConfig
from vlm_bench.types.execution import ExecutionSummary
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.rounds import LoopEnd, LoopOutcome, RoundOutcome

Step = UavStep | ArmStep


@dataclass(frozen=True)
class Execute:
    """Execute ``steps`` as round ``round`` (from where the last round left the scene)."""

    round: int
    steps: tuple[Step, ...]
    truncated: int = 0
    """Steps of the answer cut off by the step budget."""


@dataclass(frozen=True)
class Replan:
    """Ask the planner for round ``round``'s plan, telling it ``feedback``."""

    round: int
    feedback: Feedback


@dataclass(frozen=True)
class Done:
    """The episode ended."""

    outcome: LoopOutcome

    @property
    def end(self) -> LoopEnd:
        """Why it ended."""
        return self.outcome.end


Action = Execute | Replan | Done


def ran_steps(plan: Sequence[Step], outcome: RoundOutcome) -> list[ExecutedStep]:
    """The steps of ``plan`` that ran: the done ones, then the failed one (if a step failed)."""
    done = [ExecutedStep(step=s, status="done") for s in plan[: outcome.execution.n_steps_done]]
    failed = outcome.failed_step
    if failed is None:
        return done
    step = ExecutedStep(
        step=plan[failed.index], status="failed", code=str(failed.code), detail=failed.detail
    )
    return [*done, step]


class RoundMachine:
    """The rounds of one episode (see module doc).

    Args:
        max_replans: Replans after round 0 (K); 0 is the open loop.
        budget: Steps executed over all rounds (None: no limit); a replan's plan is cut to
            what is left of it, and a round that spends it ends the episode.
    """

    def __init__(self, max_replans: int = 0, budget: int | None = None) -> None:
        self.max_replans = max_replans
        self.budget = budget
        self.executed: list[ExecutedStep] = []
        """Every step run so far (done, or failed with its code and detail), all rounds."""
        self.executions: list[ExecutionSummary | None] = []
        """Each answered round's execution (None: its answer held no plan)."""
        self.feedback: Feedback | None = None
        """What the replan asked for last was told."""
        self._plan: tuple[Step, ...] = ()
        self.outcome: LoopOutcome | None = None
        """The episode's outcome, once it ended."""

    @classmethod
    def closed(cls, loop: LoopConfig, gt_steps: int) -> RoundMachine:
        """The machine of a closed-loop episode whose GT plan has ``gt_steps`` steps."""
        return cls(loop.max_rounds, loop.budget(gt_steps))

    @property
    def steps_used(self) -> int:
        """Steps executed so far (ok or failed), all rounds."""
        return len(self.executed)

    def start(self, steps: Sequence[Step] | None) -> Execute | Done:
        """Round 0's plan (None or no steps: nothing to execute); never cut by the budget."""
        if not steps:
            self.executions.append(None)
            return self._done("no_plan")
        self._plan = tuple(steps)
        self.executions.append(None)
        return Execute(0, self._plan)

    def executed_round(self, outcome: RoundOutcome) -> Replan | Done:
        """The executing round's outcome: ask for a replan, or the end."""
        self.executions[-1] = outcome.execution
        self.feedback = None
        if not outcome.crashed:
            self.executed.extend(ran_steps(self._plan, outcome))
        if outcome.execution.exec_success:
            return self._done("success")
        if len(self.executions) > self.max_replans:
            return self._done("max_rounds")
        if outcome.crashed:
            return self._done("executor_crash")
        if self.budget is not None and self.steps_used >= self.budget:
            return self._done("budget")
        self.feedback = Feedback(
            round=len(self.executions),
            executed=tuple(self.executed),
            held=outcome.held,
            incomplete=outcome.execution.steps_ok,
        )
        return Replan(self.feedback.round, self.feedback)

    def answered(self, steps: Sequence[Step] | None) -> Execute | Done:
        """The replan's answer (its valid steps; None or none: the episode ends)."""
        if self.feedback is None:
            raise RuntimeError("no replan was asked for")
        self.executions.append(None)
        if not steps:
            return self._done("no_plan")
        left = len(steps) if self.budget is None else self.budget - self.steps_used
        self._plan = tuple(steps[:left])
        return Execute(len(self.executions) - 1, self._plan, max(0, len(steps) - left))

    def _done(self, end: LoopEnd) -> Done:
        won = next(
            (i for i, e in enumerate(self.executions) if e is not None and e.exec_success), None
        )
        self.outcome = LoopOutcome(
            succ_at=tuple(won is not None and won <= k for k in range(self.max_replans + 1)),
            rounds_used=len(self.executions),
            recovered=won is not None and won > 0,
            failure_codes=tuple(
                "no_plan" if e is None else (str(e.failure_code) if e.failure_code else None)
                for e in self.executions
            ),
            steps_executed=self.steps_used,
            budget=self.budget if self.budget is not None else max(1, self.steps_used),
            end=end,
        )
        return Done(self.outcome)
