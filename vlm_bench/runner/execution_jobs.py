"""What an execution worker runs (docs/design.md#runs): an episode's rounds, in one simulation,
with the run's executor settings.

An :class:`ExecutionJob` holds every round's plan so far; the worker executes them one after
another on one :class:`~vlm_bench.executor.live_episode.LiveEpisode` and, where the last round
failed and the episode may replan, describes the state it ended in and freezes the live episode
(:mod:`~vlm_bench.executor.frozen_episode`). A job that carries the frozen episode its earlier
rounds left thaws it and executes the last round only; one without (an open-loop plan, a resume,
a retried job) executes every round from the episode's start scene. Both give the same result bit
for bit, so a job is a pure function of the episode, the settings and the plans, whichever worker
runs it. A job is picklable: it crosses to worker processes and Ray tasks. Each process keeps one
:class:`~vlm_bench.runner.plan_executor.PlanExecutor` per executor config, which keeps the
compiled scene of the episode it last executed.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass

from vlm_bench.rounds.state import RoundState, StateView
from vlm_bench.runner.plan_executor import PlanExecutor, crash_summary
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json
from vlm_bench.types.rounds import RoundOutcome

Steps = tuple[UavStep | ArmStep, ...]


@dataclass(frozen=True)
class ExecutionJob:
    """An episode's rounds to execute (picklable: crosses to worker processes)."""

    task_id: str
    seed: int
    config: ExecutorConfig
    """Gusts and perturbations: the run's, the same for every job."""
    rounds: tuple[Steps, ...]
    """Every round's plan so far (one for an open-loop plan)."""
    state: StateView | None = None
    """Describe the state after the last round when it fails (None: the episode ends)."""
    frozen: bytes | None = None
    """The live episode frozen after every round but the last (None: execute them all)."""

    @property
    def key(self) -> str:
        """Identity of the job: episode, executor settings and every round's plan."""
        text = json.dumps([plan_to_json(list(r)) for r in self.rounds], sort_keys=True)
        return f"{self.task_id}/{self.seed}/{self.config.model_dump_json()}:{text}"


@dataclass(frozen=True)
class Executed:
    """Each executed round's outcome and, where asked and the last round failed, the state."""

    outcomes: tuple[RoundOutcome, ...]
    """The rounds it executed (the last only, where it started from a frozen episode)."""
    state: RoundState | None = None
    frozen: bytes | None = None
    """The live episode frozen after the last round, where ``state`` is given (to continue)."""

    @property
    def crash(self) -> str | None:
        """The executor's exception, where it raised (the last execution says so too)."""
        last = self.outcomes[-1]
        return last.execution.failure_reason if last.crashed else None


_EXECUTORS: dict[ExecutorConfig, PlanExecutor] = {}
"""Per process (each worker's own): one executor per executor config."""


def execute_job(job: ExecutionJob) -> Executed:
    """Execute ``job``'s rounds in this process (see module doc; what every pool runs)."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.executor.frozen_episode import freeze, thaw
    from vlm_bench.rounds.state import describe_state, round_outcome
    from vlm_bench.sim.mujoco_log import route_mujoco_log
    from vlm_bench.sim.scene import build_spec
    from vlm_bench.types.execution import ExecutionSummary

    route_mujoco_log()  # a worker writes no MUJOCO_LOG.TXT either
    executor = _EXECUTORS.get(job.config)
    if executor is None:
        executor = _EXECUTORS[job.config] = PlanExecutor(job.config)
    episode = get_episode(job.task_id, job.seed)
    rounds = job.rounds
    if job.frozen is not None:
        live = thaw(job.frozen, build_spec(episode))
        rounds = rounds[-1:]
    else:
        live = executor.live(episode)
    outcomes: list[RoundOutcome] = []
    for steps in rounds:
        executor.executed += 1
        start = time.perf_counter()
        try:
            result = live.execute(list(steps))
            outcomes.append(round_outcome(result, live.held, ExecutionSummary.of(result)))
        except Exception as exc:  # noqa: BLE001  (an executor bug must not kill a long run)
            outcomes.append(
                RoundOutcome(
                    execution=crash_summary(exc, time.perf_counter() - start), crashed=True
                )
            )
            return Executed(tuple(outcomes))
    if job.state is None or outcomes[-1].execution.exec_success:
        return Executed(tuple(outcomes))
    frozen = freeze(live)  # before rendering, which must not reach the continuation
    return Executed(tuple(outcomes), describe_state(live, job.state), frozen)
