"""A closed-loop episode's rounds, executed in one simulation (what a worker runs).

A :class:`LoopJob` holds every round's plan so far; the worker executes them one after another
on one :class:`~vlm_bench.executor.live_episode.LiveEpisode` from the episode's fresh scene and,
where the last round failed and the episode may replan, describes the state it ended in (the
episode as it stands, what is held, the views) and freezes the live episode
(:mod:`~vlm_bench.executor.live_snapshot`). A job that carries the frozen state its earlier
rounds left thaws it and executes the last round only; one without (a resume, a retried
job) executes every round from the fresh scene. Both give the same result bit for bit, so a
job is a pure function of the episode, the settings and the plans, whichever worker runs it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from vlm_bench.runner.plan_executor import crash_summary
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json

Steps = tuple[UavStep | ArmStep, ...]


@dataclass(frozen=True)
class StateRequest:
    """How to show the state a failed round left."""

    views: tuple[str, ...]
    """The views to render (none for a planner that reads no images)."""
    size: int
    labels: bool


@dataclass(frozen=True)
class LoopJob:
    """An episode's rounds to execute (picklable: crosses to worker processes)."""

    task_id: str
    seed: int
    config: ExecutorConfig
    """Gusts and perturbations: the run's, the same for every job."""
    rounds: tuple[Steps, ...]
    state: StateRequest | None
    """Describe the state after the last round when it fails (None: the episode ends)."""
    snapshot: bytes | None = None
    """The live episode frozen after every round but the last (None: execute them all)."""

    @property
    def key(self) -> str:
        """Identity of the job: episode, executor settings and every round's plan."""
        plans = json.dumps([plan_to_json(list(r)) for r in self.rounds], sort_keys=True)
        return f"{self.task_id}/{self.seed}/{self.config.model_dump_json()}:{plans}"


@dataclass(frozen=True)
class LiveState:
    """The state a failed round left."""

    now: Episode
    """The episode as it stands (objects, drawers, the UAV where they are)."""
    held: str | None
    """What the gripper holds."""
    images: dict[str, bytes]
    """PNG views of the state, by view name."""
    digest: str
    """The simulator state's digest (:func:`~vlm_bench.executor.live_state.state_digest`)."""


@dataclass(frozen=True)
class RoundsExecuted:
    """Each round's execution and, where asked and the last round failed, the state."""

    executions: tuple[ExecutionSummary, ...]
    state: LiveState | None
    crash: str | None = None
    """The executor's exception, where it raised (the last execution says so too)."""
    snapshot: bytes | None = None
    """The live episode frozen after the last round, where ``state`` is given (to continue)."""


def execute_rounds(job: LoopJob) -> RoundsExecuted:
    """Execute ``job``'s rounds in this process (see module doc); the executions returned
    are those of the rounds it executed (the last only, where it started from a snapshot)."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.executor.live_episode import LiveEpisode
    from vlm_bench.executor.live_snapshot import freeze, thaw
    from vlm_bench.executor.live_state import episode_now, render_now, state_digest
    from vlm_bench.sim.mujoco_log import route_mujoco_log
    from vlm_bench.sim.scene import build_spec

    route_mujoco_log()
    episode = get_episode(job.task_id, job.seed)
    rounds = job.rounds
    if job.snapshot is not None:
        live = thaw(job.snapshot, build_spec(episode))
        rounds = rounds[-1:]
    else:
        live = LiveEpisode(episode, job.config)
    executions: list[ExecutionSummary] = []
    for steps in rounds:
        try:
            executions.append(ExecutionSummary.of(live.execute(list(steps))))
        except Exception as exc:  # noqa: BLE001  (an executor bug must not kill a long run)
            summary = crash_summary(exc, 0.0)
            executions.append(summary)
            return RoundsExecuted(tuple(executions), None, summary.failure_reason)
    state, snapshot = None, None
    if job.state is not None and not executions[-1].exec_success:
        snapshot = freeze(live)  # before rendering, which must not reach the continuation
        digest = state_digest(live)
        now = episode_now(live)
        images = render_now(live, now, job.state.views, job.state.size, job.state.labels)
        state = LiveState(now, live.held, images, digest)
    return RoundsExecuted(tuple(executions), state, snapshot=snapshot)
