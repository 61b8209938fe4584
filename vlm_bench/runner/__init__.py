"""The episode pipeline and run folders: run, resume, rescore (see :func:`run_benchmark`), and
single-plan replays (:func:`replay_plan`)."""

from vlm_bench.runner.benchmark_run import RunOutcome, make_manifest, run_benchmark
from vlm_bench.runner.cached_snapshots import SnapshotSource, snapshot_key
from vlm_bench.runner.evaluate import Evaluation, evaluate_output
from vlm_bench.runner.pipeline import EpisodePipeline, PipelineStats
from vlm_bench.runner.plan_executor import PlanExecutor, record_plan
from vlm_bench.runner.rescore import RescoreOutcome, rescore_run, score_output
from vlm_bench.runner.selection import EpisodeRef, default_run_dir, model_slug, select_episodes
from vlm_bench.runner.single_replay import Replay, VideoOptions, replay_plan
from vlm_bench.types.execution import episode_noise_seed

__all__ = [
    "EpisodePipeline",
    "EpisodeRef",
    "Evaluation",
    "PipelineStats",
    "PlanExecutor",
    "Replay",
    "RescoreOutcome",
    "RunOutcome",
    "SnapshotSource",
    "VideoOptions",
    "default_run_dir",
    "episode_noise_seed",
    "evaluate_output",
    "make_manifest",
    "model_slug",
    "record_plan",
    "replay_plan",
    "rescore_run",
    "run_benchmark",
    "score_output",
    "select_episodes",
    "snapshot_key",
]
