"""The episode pipeline and run folders: run, resume, rescore (see :func:`execute_run`)."""

from vlm_bench.runner.evaluate import Evaluation, evaluate_output
from vlm_bench.runner.pipeline import EpisodePipeline, PipelineStats
from vlm_bench.runner.rescore import RescoreOutcome, rescore_run, score_output
from vlm_bench.runner.run import RunOutcome, execute_run, make_manifest
from vlm_bench.runner.selection import EpisodeRef, default_run_dir, model_slug, select_episodes
from vlm_bench.runner.snapshots import SnapshotSource, snapshot_key

__all__ = [
    "EpisodePipeline",
    "EpisodeRef",
    "Evaluation",
    "PipelineStats",
    "RescoreOutcome",
    "RunOutcome",
    "SnapshotSource",
    "default_run_dir",
    "evaluate_output",
    "execute_run",
    "make_manifest",
    "model_slug",
    "rescore_run",
    "score_output",
    "select_episodes",
    "snapshot_key",
]
