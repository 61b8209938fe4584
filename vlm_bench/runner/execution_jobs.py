"""What an execution worker runs (docs/design.md#runs): one plan on one episode, with the run's
executor settings.

A :class:`ExecutionJob` is picklable: it crosses to worker processes and Ray tasks. Each process
keeps one :class:`~vlm_bench.runner.plan_executor.PlanExecutor` per executor config, which keeps
the compiled scene of the episode it last executed.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from vlm_bench.runner.plan_executor import PlanExecutor
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json

Executed = tuple[ExecutionSummary, str | None]
"""An execution's summary and, where the executor raised, the message (the summary says so too)."""


@dataclass(frozen=True)
class ExecutionJob:
    """One plan to execute on one episode (picklable: crosses to worker processes)."""

    task_id: str
    seed: int
    config: ExecutorConfig
    """Gusts and perturbations: the run's, the same for every job."""
    steps: tuple[UavStep | ArmStep, ...]

    @property
    def key(self) -> str:
        """Identity of the execution: episode, executor settings and plan."""
        plan = json.dumps(plan_to_json(list(self.steps)), sort_keys=True)
        return f"{self.task_id}/{self.seed}/{self.config.model_dump_json()}:{plan}"


_EXECUTORS: dict[ExecutorConfig, PlanExecutor] = {}
"""Per process (each worker's own): one executor per executor config."""


def execute_job(job: ExecutionJob) -> Executed:
    """Execute ``job`` in this process (what every pool runs)."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.sim.mujoco_log import route_mujoco_log

    route_mujoco_log()  # a worker writes no MUJOCO_LOG.TXT either
    executor = _EXECUTORS.get(job.config)
    if executor is None:
        executor = _EXECUTORS[job.config] = PlanExecutor(job.config)
    episode = get_episode(job.task_id, job.seed)
    return executor.execute(episode, list(job.steps))
