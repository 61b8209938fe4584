"""Execute the plans of a run's records in the simulator (runs and rescore; docs/design.md#runs).

The executable plan of a record is its parse's valid steps (what ``record.plan`` holds); an
output with no usable plan is not executed (``execution`` stays None and the episode counts as
not successful). Execution never stops a run: an exception from the executor becomes a failed
:class:`~vlm_bench.types.execution.ExecutionSummary` with code
:attr:`~vlm_bench.types.execution.FailureCode.EXECUTOR_CRASH` and the exception as its
reason. The simulator is imported only when a plan is executed.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig, FailureCode
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.records import EpisodeRecord

if TYPE_CHECKING:
    from vlm_bench.executor.live_episode import LiveEpisode
    from vlm_bench.sim.scene import Scene

CRASH_PREFIX = "executor raised"
"""Start of the failure reason of an execution that ended in an exception."""


def record_plan(record: EpisodeRecord) -> list[UavStep | ArmStep] | None:
    """The steps to execute for ``record``; None when there is no usable, non-empty plan."""
    if not record.ok or record.parse is None or not record.parse.usable:
        return None
    return record.parse.valid_steps() or None


def crash_summary(exc: Exception, wall_time_s: float) -> ExecutionSummary:
    """A failed execution standing for an exception raised by the executor."""
    return ExecutionSummary(
        exec_success=False,
        steps_ok=False,
        n_steps_done=0,
        s_task=0.0,
        sim_time_s=0.0,
        failure_reason=f"{CRASH_PREFIX} {type(exc).__name__}: {exc}",
        failure_code=FailureCode.EXECUTOR_CRASH,
        wall_time_s=max(0.0, wall_time_s),
    )


class PlanExecutor:
    """Executes plans with one :class:`ExecutorConfig`; compiles each episode's scene once
    and executes on copies (a worker keeps one per config: :func:`.execution_jobs.execute_job`).

    Identical plans are not de-duplicated here: the runner sends each (episode, plan) once.
    """

    def __init__(self, config: ExecutorConfig | None = None) -> None:
        self.config = config or ExecutorConfig()
        self.executed = 0
        """Plans executed."""
        self._template: tuple[tuple[str, int], Scene] | None = None

    def scene(self, episode: Episode) -> Scene:
        """A fresh copy of the episode's start scene (the executor modifies the scene it runs)."""
        from vlm_bench.executor.step_execution import episode_scene

        key = (episode.task_id, episode.seed)
        if self._template is None or self._template[0] != key:
            self._template = (key, episode_scene(episode, self.config))
        return self._template[1].copy()

    def live(self, episode: Episode) -> LiveEpisode:
        """A live episode on a fresh copy of the episode's start scene."""
        from vlm_bench.executor.live_episode import LiveEpisode

        return LiveEpisode(episode, self.config, self.scene(episode))

    def execute(
        self, episode: Episode, steps: list[UavStep | ArmStep]
    ) -> tuple[ExecutionSummary, str | None]:
        """Execute ``steps`` on the episode: the summary and, where the executor raised, the
        message (an exception becomes a failed summary)."""
        start = time.perf_counter()
        self.executed += 1
        try:
            result = self.live(episode).execute(steps)
            summary = ExecutionSummary.of(result)  # rejects a non-finite number
        except Exception as exc:  # noqa: BLE001  (an executor bug must not kill a long run)
            summary = crash_summary(exc, time.perf_counter() - start)
            return summary, summary.failure_reason
        return summary, None
