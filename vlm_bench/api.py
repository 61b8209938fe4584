"""The public Python API: run a model, rescore a run, score one output, load a run.

Example:
    >>> import vlm_bench
    >>> result = vlm_bench.run(model="oracle", suite="long_horizon", seeds=(0, 1), resolution=64)
    >>> result.summary  # the paper's table in long form (one row per model × instruction × suite)

The CLI (``vlm-bench run/rescore/score``) is a thin layer over these functions.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vlm_bench.errors import ConfigError
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunConfig, RunManifest, run_config
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.task import InstructionVariant

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped, unused-ignore]

    from vlm_bench.backends import Backend

__all__ = ["RunConfig", "RunResult", "load_run", "rescore", "run", "run_dir_for", "score_output"]


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
    stats: dict[str, int]
    """Counts of this call: total, skipped, scored, errors, cached, generate_calls, changed."""

    @property
    def run_id(self) -> str:
        """The run id (the folder's name)."""
        return self.run_dir.name

    def frame(self) -> pd.DataFrame:
        """One row per episode (see :func:`vlm_bench.report.records_frame`)."""
        from vlm_bench.report import records_frame

        return records_frame(self.records)

    def table(self) -> pd.DataFrame:
        """The paper layout: rows model × instruction, columns (suite, metric)."""
        from vlm_bench.report import summary_wide

        return summary_wide(self.summary)


def run_dir_for(config: RunConfig, out: Path | str | None = None, run_name: str | None = None,
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
        progress: Show a progress bar on stderr.
        **options: :class:`RunConfig` fields when ``config`` is None (``model="oracle"``, ...).

    Returns:
        The folder's records and summary; ``summary.md``/``summary.csv`` are written too.

    Raises:
        ConfigError: Invalid options. RunLockedError / ConfigMismatchError: see the CLI docs.
    """
    from vlm_bench.report import write_summary
    from vlm_bench.runner import execute_run

    if config is None:
        config = run_config(**options)
    elif options:
        raise ConfigError("give a RunConfig or keyword options, not both")
    outcome = execute_run(config, run_dir_for(config, out, run_name), backend=backend,
                          snapshot_cache=snapshot_cache, progress=progress)
    summary = write_summary(outcome.run_dir)
    s = outcome.stats
    stats = {"total": s.total, "skipped": s.skipped, "scored": s.scored, "errors": s.errors,
             "cached": s.cached, "generate_calls": s.generate_calls}
    return RunResult(outcome.run_dir, outcome.manifest, outcome.records, summary, stats)


def rescore(run_dir: Path | str) -> RunResult:
    """Recompute parses and scores of a run from its response cache; no model is called.

    Rewrites ``records.jsonl`` (one line per episode) and the summary files.
    """
    from vlm_bench.report import write_summary
    from vlm_bench.runner import rescore_run

    outcome = rescore_run(Path(run_dir))
    summary = write_summary(outcome.run_dir)
    stats = {"total": len(outcome.records), "changed": outcome.changed, "generate_calls": 0}
    return RunResult(outcome.run_dir, outcome.manifest, outcome.records, summary, stats)


def load_run(run_dir: Path | str) -> RunResult:
    """Read a run folder (manifest, latest records, summary) without writing anything."""
    from vlm_bench.report import records_frame, summary_long
    from vlm_bench.storage import RunPaths, latest_records, read_manifest

    paths = RunPaths(Path(run_dir))
    manifest = read_manifest(paths)
    records = tuple(latest_records(paths.records))
    return RunResult(paths.root, manifest, records, summary_long(records_frame(records)),
                     {"total": len(records)})


def score_output(
    task_id: str, seed: int, text: str, instruction: InstructionVariant = "explicit",
    scoring: ScoringConfig | None = None,
) -> dict[str, Any]:
    """Score one raw model output against an episode's GT plan.

    Returns:
        JSON-ready dict with ``task_id, seed, instruction, parse, plan, gt_plan, scores,
        error_tags``.
    """
    from vlm_bench.runner import score_output as _score

    return _score(task_id, seed, text, instruction, scoring)
