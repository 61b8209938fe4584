"""Run a configuration into a run folder: create or resume, evaluate (and execute) pending
episodes, close."""

from __future__ import annotations

import platform
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from vlm_bench.backends import Backend, operational_args, resolve_backend
from vlm_bench.backends.preflight import BackendCheck, check_backend, loads_model_in_process
from vlm_bench.backends.rules_planner import NO_SCENE
from vlm_bench.errors import ConfigError, VlmBenchError
from vlm_bench.runner.cached_snapshots import SnapshotSource, check_resolution
from vlm_bench.runner.episode_request import run_snapshots
from vlm_bench.runner.executions import Executions, make_pool
from vlm_bench.runner.interrupt import deferred_interrupt
from vlm_bench.runner.pipeline import EpisodePipeline, PipelineStats
from vlm_bench.runner.progress import RunProgress
from vlm_bench.runner.selection import run_protocol, select_episodes
from vlm_bench.sim.mujoco_log import route_mujoco_log
from vlm_bench.storage import (
    RunStore,
    SnapshotCache,
    data_hashes,
    default_snapshot_cache,
    git_revision,
    package_versions,
)
from vlm_bench.storage.provenance import machine
from vlm_bench.types.benchmark_version import require_current_version
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.records import EpisodeRecord, utc_now
from vlm_bench.types.run import RunConfig, RunManifest


@dataclass(frozen=True)
class RunOutcome:
    """What a run (or resume) left in its folder."""

    run_dir: Path
    manifest: RunManifest
    records: tuple[EpisodeRecord, ...]
    """The latest record of every episode of the folder, in run order."""
    stats: PipelineStats


def make_manifest(config: RunConfig, backend_name: str) -> Callable[[str], RunManifest]:
    """A builder of the run's manifest for a run id (provenance is gathered when called)."""

    operational = operational_args(config.model)

    def build(run_id: str) -> RunManifest:
        return RunManifest(
            run_id=run_id,
            config=config.redacted(),
            config_hash=config.config_hash(operational),
            operational_args=tuple(sorted(operational)),
            backend=backend_name,
            data=data_hashes(),
            packages=package_versions(),
            git_revision=git_revision(),
            python=platform.python_version(),
            platform=machine(),
            created=utc_now(),
            protocol=run_protocol(config),
        )

    return build


def _load_backend(config: RunConfig) -> Backend:
    """Build the run's backend; a model that fails to load is a one-line error naming it.

    Raises:
        ConfigError: The backend's loader raised (e.g. a corrupt checkpoint, an unsupported
            architecture, a server refusing the model); the message keeps its first line.
    """
    try:
        return resolve_backend(config.model, config.backend_args)
    except VlmBenchError:
        raise
    except Exception as exc:  # noqa: BLE001  (loaders raise anything: OSError, ValueError, ...)
        lines = str(exc).strip().splitlines()
        detail = lines[0][:300] if lines else ""
        raise ConfigError(
            f"cannot load model {config.model!r}: {type(exc).__name__}: {detail}"
        ) from None


class _LazyBackend:
    """Builds the backend on first use (a finished resume never loads the model)."""

    def __init__(self, config: RunConfig, given: Backend | None) -> None:
        self.config = config
        self.backend = given
        self.owned = given is None

    def __call__(self) -> Backend:
        if self.backend is None:
            self.backend = _load_backend(self.config)
        return self.backend

    def close(self) -> None:
        if self.owned and self.backend is not None:
            self.backend.close()


def _check_backend(config: RunConfig, given: Backend | None) -> BackendCheck:
    """The run's backend, checked without loading a model (a given instance is trusted)."""
    if given is not None:
        name = given.name
        return BackendCheck(name, config.model, loads_model_in_process(name), given.sees_images)
    return check_backend(
        config.model, config.backend_args, constrained=config.generation.constrained
    )


@contextmanager
def _snapshot_source(
    config: RunConfig, cache_dir: Path | None, sees_images: bool
) -> Iterator[SnapshotSource]:
    cache = SnapshotCache(cache_dir) if cache_dir is not None else None
    source = run_snapshots(config, cache) if sees_images else SnapshotSource((), 0)
    try:
        yield source
    finally:
        source.close()


def _executions(
    config: RunConfig,
    options: ExecutionOptions | None,
    on_change: Callable[[int, int, int, int], None],
    sees_images: bool,
) -> Executions | None:
    """Where the run's episodes execute (None: the run does not execute plans)."""
    if not config.execute:
        return None
    options = options or ExecutionOptions()
    return Executions(make_pool(options), config, on_change, options.stall_s, sees_images)


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
    require_current_version(config.benchmark_version, "the run's config")
    check_resolution(config.resolution)
    refs = select_episodes(config)
    checked = _check_backend(config, backend)  # before the folder is written
    backend_name = checked.name
    if backend_name == "rules" and not config.scene_as_text:
        raise ConfigError(NO_SCENE)
    route_mujoco_log()  # (the renderer preloads what must precede EGL: sim/gl_preload.py)
    cache_dir = (
        default_snapshot_cache(run_dir) if snapshot_cache is True else snapshot_cache or None
    )
    lazy = _LazyBackend(config, backend)
    with (
        RunStore.create_or_resume(run_dir, config, make_manifest(config, backend_name)) as store,
        _snapshot_source(config, cache_dir, checked.sees_images) as snapshots,
        RunProgress(len(refs), store.paths.run_id, enabled=progress) as shown,
        deferred_interrupt() as stop,
    ):
        sees = checked.sees_images
        executions = _executions(config, execution, shown.executions_changed, sees)
        try:
            pipeline = EpisodePipeline(
                config, store, lazy, snapshots, shown, stop, executions, sees_images=sees
            )
            stats = pipeline.run(refs)
        finally:
            lazy.close()
        records = tuple(store.records[r.key] for r in refs if r.key in store.records)
        return RunOutcome(store.paths.root, store.manifest, records, stats)
