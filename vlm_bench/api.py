"""The public Python API: run a model, rescore a run, score one output, load a run.

Example:
    >>> import vlm_bench
    >>> result = vlm_bench.run(model="oracle", suite="long_horizon", seeds=(0, 1), resolution=64)
    >>> result.summary  # the paper's table in long form (one row per model × instruction × suite)
    >>> vlm_bench.execute("drawer_interaction", 3).result.exec_success  # execute the GT plan

Runs execute every valid plan in the simulator unless ``execute=False``; ``uav_noise=2.0``
adds gusts on the UAV (the paper's "UAV Disturb." condition). The CLI (``vlm-bench
run/rescore/score/execute``) is a thin layer over these functions.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vlm_bench.errors import ConfigError
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.records import EpisodeRecord, OutputScore
from vlm_bench.types.run import RunConfig, RunManifest, run_config
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.task import InstructionVariant

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped, unused-ignore]

    from vlm_bench.backends import Backend
    from vlm_bench.runner import PipelineStats
    from vlm_bench.runner.episode_request import PromptPreview
    from vlm_bench.runner.task_execution import ExecutedPlan

__all__ = [
    "RunConfig",
    "RunResult",
    "execute",
    "load_run",
    "preview_prompt",
    "rescore",
    "run",
    "run_dir_for",
    "score_output",
]


@dataclass(frozen=True)
class RunResult:
    """A run folder's content after a run, resume or rescore."""

    run_dir: Path
    """The run folder."""
    manifest: RunManifest
    """Config and provenance."""
    records: tuple[EpisodeRecord, ...]
    """The latest record of every episode, in run order."""
    summary: pd.DataFrame
    """Long summary: model × instruction × suite (+ overall, both) rows; see report.summary."""
    stats: PipelineStats
    """Counts of this call (a rescore fills total, executed and changed; a load, total)."""

    @property
    def run_id(self) -> str:
        """The run id (the folder's name)."""
        return self.run_dir.name

    def frame(self) -> pd.DataFrame:
        """One row per episode (see :func:`vlm_bench.report.records_frame`)."""
        from vlm_bench.report import records_frame

        return records_frame(self.records, {self.manifest.run_id: self.manifest.config.execute})

    def table(self) -> pd.DataFrame:
        """The paper layout: rows model × instruction, columns (suite, metric)."""
        from vlm_bench.report import summary_wide

        return summary_wide(self.summary)


def run_dir_for(
    config: RunConfig,
    out: Path | str | None = None,
    run_name: str | None = None,
) -> Path:
    """The run folder: ``out``, ``results/<run_name>``, or ``results/<model-slug>-<hash>``."""
    from vlm_bench.resources import results_dir
    from vlm_bench.runner import default_run_dir

    if out is not None and run_name is not None:
        raise ConfigError("give --out or --run-name, not both")
    if out is not None:
        return Path(out)
    if run_name is not None:
        if not run_name or "/" in run_name or run_name.startswith("."):
            raise ConfigError(f"run name must be a plain folder name, got {run_name!r}")
        return results_dir() / run_name
    return default_run_dir(config)


def run(
    config: RunConfig | None = None,
    *,
    out: Path | str | None = None,
    run_name: str | None = None,
    backend: Backend | None = None,
    snapshot_cache: Path | bool | None = True,
    progress: bool = False,
    execution: ExecutionOptions | None = None,
    protocol: str | None = None,
    **options: Any,
) -> RunResult:
    """Evaluate a model's plans on the benchmark, resuming the run folder if it exists.

    Args:
        config: The run configuration, or None to build one from ``options``.
        out: Run folder. Default: ``results/<model-slug>-<short config hash>``.
        run_name: Folder name under ``results/`` (instead of ``out``).
        backend: A backend instance to use instead of resolving ``config.model``.
        snapshot_cache: PNG cache folder; True = ``.snapshots`` beside the run folder (or
            ``VLM_BENCH_SNAPSHOT_CACHE``); False/None = render every episode.
        progress: Show progress on stderr.
        execution: Where plans are executed (default: one worker process per core, beside
            generation; ``ExecutionOptions(workers=0)`` executes inline).
        **options: :class:`RunConfig` fields when ``config`` is None (``model="oracle"``,
            ``execute=False`` to skip plan execution, ``uav_noise=2.0`` for gusts,
            ``loop="closed", max_rounds=3`` to replan after failures,
            ``perturb="slip=0.3,bump=0.3"`` (or a ``PerturbConfig``), ...).
        protocol: A stated protocol (``paper``, ``closed``; docs/protocols.md): fields not
            given take its values; given selection fields may narrow its episodes.

    Returns:
        The folder's records and summary; ``summary.md``/``summary.csv`` and
        ``results.json`` are written too.

    Raises:
        ConfigError: Invalid options. RunLockedError / ConfigMismatchError: see the CLI docs.
    """
    from vlm_bench.report import write_summary
    from vlm_bench.report.results_file import write_results
    from vlm_bench.runner import run_benchmark

    if config is None:
        if isinstance(options.get("perturb"), str):
            from vlm_bench.executor.perturbations import perturb_options

            noise = options.get("uav_noise", 0.0)
            options["perturb"], options["uav_noise"] = perturb_options(options["perturb"], noise)
        config = run_config(**options)
    elif options:
        raise ConfigError("give a RunConfig or keyword options, not both")
    if protocol is not None:
        from vlm_bench.types.protocol_match import with_protocol

        given = set(options) if options else set(config.model_fields_set)
        config = with_protocol(config, protocol, given)
    outcome = run_benchmark(
        config,
        run_dir_for(config, out, run_name),
        backend=backend,
        snapshot_cache=snapshot_cache,
        progress=progress,
        execution=execution,
    )
    summary = write_summary(outcome.run_dir)
    write_results(outcome.run_dir)
    return RunResult(outcome.run_dir, outcome.manifest, outcome.records, summary, outcome.stats)


def rescore(
    run_dir: Path | str, *, progress: bool = False, execution: ExecutionOptions | None = None
) -> RunResult:
    """Recompute parses and scores of a run from its response cache; no model is called.

    A run that executes plans executes them all again, in the pool ``execution`` asks for
    (default: one worker process per core). Rewrites ``records.jsonl`` (one line per episode,
    in its order) and the summary files.
    """
    from vlm_bench.report import write_summary
    from vlm_bench.report.results_file import write_results
    from vlm_bench.runner import PipelineStats, rescore_run

    outcome = rescore_run(Path(run_dir), progress=progress, execution=execution)
    summary = write_summary(outcome.run_dir)
    write_results(outcome.run_dir)
    stats = PipelineStats(
        total=len(outcome.records),
        executed=outcome.executed,
        changed=outcome.changed,
        torn_bytes=outcome.torn_bytes,
    )
    return RunResult(outcome.run_dir, outcome.manifest, outcome.records, summary, stats)


def load_run(run_dir: Path | str) -> RunResult:
    """Read a run folder (manifest, latest records, summary) without writing anything."""
    from vlm_bench.report import records_frame, summary_long
    from vlm_bench.runner import PipelineStats
    from vlm_bench.storage import RunPaths, latest_records, read_manifest

    paths = RunPaths(Path(run_dir))
    manifest = read_manifest(paths)
    records = tuple(latest_records(paths.records))
    frame = records_frame(records, {manifest.run_id: manifest.config.execute})
    stats = PipelineStats(total=len(records))
    return RunResult(paths.root, manifest, records, summary_long(frame), stats)


def preview_prompt(
    task_id: str,
    seed: int,
    instruction: InstructionVariant = "explicit",
    *,
    snapshot_cache: Path | bool | None = True,
    **options: Any,
) -> PromptPreview:
    """The prompt and request a run sends for one episode, built by the run's own code.

    Args:
        task_id: Task id.
        seed: Episode seed.
        instruction: Instruction variant.
        snapshot_cache: PNG cache folder; True = the one runs under ``results/`` share (or
            ``VLM_BENCH_SNAPSHOT_CACHE``); False/None = render.
        **options: The run's prompt options as :class:`RunConfig` fields (``views``,
            ``resolution``, ``k_shot``, ``object_list``, ``images``, ``scene_as_text``,
            ``generation``, ...).

    Returns:
        :class:`~vlm_bench.runner.episode_request.PromptPreview`: ``.text()`` shows the system
        and user turns, ``.request`` is what the backend gets, ``.write_images(folder)``.

    Raises:
        ConfigError: An invalid option. UnknownNameError: An unknown task.
    """
    from vlm_bench.resources import results_dir
    from vlm_bench.runner.episode_request import preview_request
    from vlm_bench.storage import default_snapshot_cache

    fields = {"model": "preview", **options}
    config = run_config(tasks=(task_id,), seeds=(seed,), instructions=(instruction,), **fields)
    if snapshot_cache is True:
        cache: Path | None = default_snapshot_cache(results_dir() / "preview")  # shared
    else:
        cache = Path(snapshot_cache) if snapshot_cache else None
    return preview_request(config, cache)


def execute(
    task_id: str,
    seed: int,
    plan: str | None = None,
    *,
    source: str = "plan",
    instruction: InstructionVariant = "explicit",
    uav_noise: float = 0.0,
    video: Path | str | None = None,
    camera: str = "side",
    fps: float = 10.0,
    size: int = 480,
    shadows: bool = True,
) -> ExecutedPlan:
    """Execute one plan on an episode in the simulator (the GT plan when ``plan`` is None).

    Args:
        task_id: Task id.
        seed: Episode seed.
        plan: Plan text in the paper's JSON format (as a model would answer), or None.
        source: The plan's origin, named in error messages (e.g. its file name).
        instruction: Instruction variant the plan answers (a label; both share the scene).
        uav_noise: Gust force std on the UAV (N), seeded per episode as in runs.
        video: Write a video of the execution here (``.mp4`` needs the ``video`` extra, ``.gif``
            does not).
        camera: Camera filmed (``uav``, ``wrist``, ``overhead``, ``side``, ...).
        fps: Video frames per second (at most 20, the control rate).
        size: Video frame side in pixels.
        shadows: Render the video with shadows (2–3× slower per frame on a CPU).

    Returns:
        The :class:`~vlm_bench.runner.task_execution.ExecutedPlan`: the plan, the
        :class:`~vlm_bench.types.execution.ExecutionResult`, goal labels and the video path.

    Raises:
        ConfigError: An invalid plan (names the step) or option. UnknownNameError: Unknown task
        or camera. MissingExtraError: MP4 without imageio-ffmpeg.
    """
    from vlm_bench.runner.task_execution import VideoOptions, execute_task_plan

    options = VideoOptions(Path(video), camera, fps, size, shadows) if video is not None else None
    return execute_task_plan(
        task_id, seed, plan, source=source, variant=instruction, uav_noise=uav_noise, video=options
    )


def score_output(
    task_id: str,
    seed: int,
    text: str,
    instruction: InstructionVariant = "explicit",
    scoring: ScoringConfig | None = None,
) -> OutputScore:
    """Score one raw model output against an episode's GT plan.

    Returns:
        The parse, the valid predicted steps, the GT plan, the scores and the error tags
        (``.model_dump(mode="json")`` for JSON).
    """
    from vlm_bench.runner import score_output as _score

    return _score(task_id, seed, text, instruction, scoring)
