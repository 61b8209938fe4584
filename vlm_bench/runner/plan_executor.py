"""Replay the plans of a run's records in the simulator (runs and rescore; docs/design.md#runs).

The executable plan of a record is its parse's valid steps (what ``record.plan`` holds); an
output with no usable plan is not executed (``execution`` stays None and the episode counts as
not successful). Execution never stops a run: an exception from the executor becomes a failed
:class:`~vlm_bench.types.execution.ExecutionSummary` with code
:attr:`~vlm_bench.types.execution.FailureCode.EXECUTOR_CRASH` and the exception as its
reason. The simulator is imported only when a plan is executed.
"""

from __future__ import annotations

import hashlib
import json
import time
from typing import TYPE_CHECKING

from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig, FailureCode
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json
from vlm_bench.types.records import EpisodeRecord

if TYPE_CHECKING:
    from vlm_bench.sim.scene import Scene

CRASH_PREFIX = "executor raised"
"""Start of the failure reason of an execution that ended in an exception."""


def episode_noise_seed(task_id: str, seed: int) -> int:
    """Seed of an episode's gusts: stable across runs and machines, and shared by both
    instruction variants (so their executions face the same wind)."""
    digest = hashlib.sha256(f"uav-noise|{task_id}|{seed}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


def executor_config(episode: Episode, uav_noise: float) -> ExecutorConfig:
    """The benchmark's executor settings with ``uav_noise`` and the episode's gust seed."""
    return ExecutorConfig(
        uav_noise=uav_noise, noise_seed=episode_noise_seed(episode.task_id, episode.seed)
    )


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
    """Executes records' plans; compiles each episode's scene once and replays on copies.

    Args:
        uav_noise: Gust force std on the UAV (N); 0 = calm.
        perturb: Seeded perturbations (None: none).
    """

    def __init__(self, uav_noise: float = 0.0, perturb: PerturbConfig | None = None) -> None:
        self.uav_noise = uav_noise
        self.perturb = perturb
        self.executed = 0
        """Plans executed."""
        self._template: tuple[tuple[str, int], Scene] | None = None
        self._memo: dict[str, ExecutionSummary] = {}
        """Summaries of the current episode's plans: the simulation is deterministic, so the
        same plan on the same scene (e.g. both instruction variants) is executed once."""
        self.reused = 0
        """Executions answered from the memo."""

    def scene(self, episode: Episode) -> Scene:
        """A fresh copy of the episode's start scene (the executor modifies the scene it runs)."""
        from vlm_bench.executor.plan_replay import episode_scene

        key = (episode.task_id, episode.seed)
        if self._template is None or self._template[0] != key:
            self._template = (key, episode_scene(episode, executor_config(episode, self.uav_noise)))
            self._memo.clear()
        return self._template[1].copy()

    def summary(self, episode: Episode, steps: list[UavStep | ArmStep]) -> ExecutionSummary:
        """Execute ``steps`` on the episode; an exception becomes a failed summary."""
        return self.run(episode, steps)[0]

    def run(
        self, episode: Episode, steps: list[UavStep | ArmStep]
    ) -> tuple[ExecutionSummary, str | None]:
        from vlm_bench import executor

        memo_key = f"{episode.task_id}/{episode.seed}:" + json.dumps(plan_to_json(steps))
        if memo_key in self._memo:
            self.reused += 1
            return self._memo[memo_key], None
        start = time.perf_counter()
        self.executed += 1
        try:
            result = executor.execute_plan(
                episode,
                steps,
                executor_config(episode, self.uav_noise),
                self.scene(episode),
                perturb=self.perturb,
            )
            summary = ExecutionSummary.of(result)  # rejects a non-finite number
        except Exception as exc:  # noqa: BLE001  (an executor bug must not kill a long run)
            summary = crash_summary(exc, time.perf_counter() - start)
            return summary, summary.failure_reason
        self._memo[memo_key] = summary
        return summary, None
