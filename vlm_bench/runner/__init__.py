"""The episode pipeline and run folders: run, resume, rescore (see :func:`run_benchmark`), and
single-plan executions (:func:`execute_task_plan`)."""

from vlm_bench.runner.benchmark_run import run_benchmark
from vlm_bench.runner.cached_snapshots import SnapshotSource
from vlm_bench.runner.pipeline import PipelineStats
from vlm_bench.runner.plan_executor import PlanExecutor, record_plan
from vlm_bench.runner.rescore import rescore_run, score_output
from vlm_bench.runner.selection import default_run_dir
from vlm_bench.types.execution import episode_noise_seed

__all__ = [
    "PipelineStats",
    "PlanExecutor",
    "SnapshotSource",
    "default_run_dir",
    "episode_noise_seed",
    "record_plan",
    "rescore_run",
    "run_benchmark",
    "score_output",
]
