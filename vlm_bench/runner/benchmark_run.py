"""Run a configuration into a run folder: create or resume, evaluate (and execute) pending
episodes, close."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from vlm_bench.backends import Backend
from vlm_bench.runner.answers import ModelAnswers
from vlm_bench.runner.cached_snapshots import SnapshotSource
from vlm_bench.runner.execution_pools import make_pool
from vlm_bench.runner.interrupt import deferred_interrupt
from vlm_bench.runner.pipeline import EpisodePipeline, PipelineStats
from vlm_bench.runner.progress import RunProgress
from vlm_bench.runner.run_plan import plan_run
from vlm_bench.sim.mujoco_log import route_mujoco_log
from vlm_bench.storage import RunStore, SnapshotCache, default_snapshot_cache
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunConfig, RunManifest


@dataclass(frozen=True)
class RunOutcome:
    """What a run (or resume) left in its folder."""

    run_dir: Path
    manifest: RunManifest
    records: tuple[EpisodeRecord, ...]
    """The latest record of every episode of the folder, in run order."""
    stats: PipelineStats


def run_benchmark(
    config: RunConfig,
    run_dir: Path,
    *,
    backend: Backend | None = None,
    snapshot_cache: Path | bool | None = True,
    progress: bool = True,
    execution: ExecutionOptions | None = None,
) -> RunOutcome:
    """Evaluate the configuration's episodes into ``run_dir``, resuming what is there.

    Args:
        config: The run configuration.
        run_dir: The run folder (created if missing).
        backend: A backend instance to use instead of resolving ``config.model``.
        snapshot_cache: Folder of the shared PNG cache; True = the default
            (:func:`~vlm_bench.storage.default_snapshot_cache`), False/None = no cache.
        progress: Show progress on stderr.
        execution: Where plans are executed (default: one worker process per core, overlapped
            with generation).

    A start that fails before any episode is written removes the folder it created, so the
    corrected command starts clean.

    Raises:
        ConfigError: Invalid options (e.g. a resolution above the offscreen buffer), an unknown
            model or a bad backend argument (checked before the folder is written).
        MissingExtraError: The backend's optional dependency is not installed.
        UnknownNameError: Unknown task ids.
        RunLockedError: Another process writes the folder.
        ConfigMismatchError: The folder holds a run with another configuration.
        BenchmarkVersionError: The config asks for another benchmark version than this
            release's.
    """
    plan = plan_run(config, backend)  # before the folder is written
    route_mujoco_log()  # (the renderer preloads what must precede EGL: sim/gl_preload.py)
    cache_dir = (
        default_snapshot_cache(run_dir) if snapshot_cache is True else snapshot_cache or None
    )
    cache = SnapshotCache(cache_dir) if cache_dir is not None else None
    shown = plan.shown
    options = execution or ExecutionOptions()
    with (
        RunStore.create_or_resume(run_dir, config, plan.manifest) as store,
        SnapshotSource(shown.views, shown.size, shown.labels, cache) as snapshots,
        RunProgress(len(plan.episodes), store.paths.run_id, enabled=progress) as bar,
        deferred_interrupt() as stop,
    ):
        answers = ModelAnswers(config.model, config.backend_args, plan.generation, store, backend)
        pool = make_pool(options) if plan.executor is not None else None
        try:
            pipeline = EpisodePipeline(
                plan, store, answers, snapshots, bar, stop, pool, options.stall_s
            )
            stats = pipeline.run()
        finally:
            answers.close()
        keys = [r.key for r in plan.episodes]
        records = tuple(store.records[k] for k in keys if k in store.records)
        return RunOutcome(store.paths.root, store.manifest, records, stats)
