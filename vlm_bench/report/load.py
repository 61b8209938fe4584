"""``load(*runs)``: one tidy row per episode of any number of run folders, with their settings.

The rows are :func:`vlm_bench.report.dataframe.records_frame`'s, plus the run's settings from its
manifest (:data:`SETTINGS`, so that ``--by views,resolution`` compares ablations) and a few
columns derived from the record (:data:`DERIVED`).
"""

from __future__ import annotations

import glob
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import ConfigError
from vlm_bench.report.dataframe import records_frame
from vlm_bench.report.groups import paper_grouping
from vlm_bench.storage import RunPaths, latest_records, read_manifest
from vlm_bench.types.benchmark_version import check_one_version
from vlm_bench.types.plan import Direction
from vlm_bench.types.protocol_match import manifest_protocol
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.results import RESULTS_FILE
from vlm_bench.types.run import RunManifest

SETTINGS = (
    "backend",
    "views",
    "n_views",
    "resolution",
    "labels",
    "k_shot",
    "few_shot_seed",
    "object_list",
    "images",
    "scene_as_text",
    "constrained",
    "temperature",
    "max_new_tokens",
    "loc_alignment",
    "execute",
    "uav_noise",
    "benchmark_version",
    "config_hash",
    "git_revision",
    "protocol",
)
"""Run settings from the manifest, one column each (``views`` joined by commas; ``protocol``
is the run's stated protocol: paper, closed or custom, docs/protocols.md)."""

DERIVED = (
    "run",
    "run_dir",
    "paper_column",
    "first_move",
    "pred_first_move",
    "gt_steps",
    "pred_steps",
    "repairs",
)
"""Columns derived per episode: ``run`` (the folder's name, made unique), its path, the paper's
table column (:mod:`vlm_bench.report.groups`), the GT's and the prediction's first horizontal
UAV move (the sector S_loc is hardest on), the step counts and the parser's repairs."""

MIXED_VERSIONS_HINT = "compare runs of one version, or pass --mixed-versions (mixed_versions=True)"
"""How to put runs of different benchmark versions in one table anyway."""

_HORIZONTAL = {d.value for d in Direction if d.is_horizontal}


def resolve_runs(patterns: Iterable[str | Path]) -> list[Path]:
    """Run folders named by paths or glob patterns, each once, in the order given.

    A glob keeps only the folders that hold a ``manifest.json``; a file is skipped (a glob the
    shell expanded names files too).

    Raises:
        ConfigError: No run folder, a path that does not exist, a folder that is no run, or a
            pattern that matches no run (one line naming it).
    """
    out: list[Path] = []
    for pattern in patterns:
        text = str(pattern)
        if glob.has_magic(text):
            found = [
                Path(p) for p in sorted(glob.glob(text)) if RunPaths(Path(p)).manifest.exists()
            ]
            if not found:
                raise ConfigError(f"no run folder matches {text!r}")
        else:
            path = Path(text)
            if path.name == RESULTS_FILE and RunPaths(path.parent).manifest.exists():
                path = path.parent  # a run folder's results.json stands for the folder
            elif path.is_file():
                continue  # a shell-expanded glob also names files (results/README.md)
            if not path.is_dir():
                raise ConfigError(f"run folder {text!r} does not exist")
            if not RunPaths(path).manifest.exists():
                inside = any(RunPaths(p).manifest.exists() for p in path.iterdir() if p.is_dir())
                hint = f"; for the runs inside it give '{path / '*'}'" if inside else ""
                raise ConfigError(
                    f"{text!r} is not a vlm-bench run folder (no manifest.json){hint}"
                )
            found = [path]
        out.extend(p for p in found if p.resolve() not in {q.resolve() for q in out})
    if not out:
        raise ConfigError("no run folder given")
    return out


def run_labels(paths: Sequence[Path]) -> list[str]:
    """Short unique names: the folder name, with its parents where two names clash."""
    depth = 1
    while True:
        labels = ["/".join(p.resolve().parts[-depth:]) for p in paths]
        if len(set(labels)) == len(labels) or depth > 8:
            return labels
        depth += 1


def settings_of(manifest: RunManifest) -> dict[str, Any]:
    """The :data:`SETTINGS` values of one run."""
    config = manifest.config
    return {
        "backend": manifest.backend,
        "views": ",".join(config.views) if config.images else "",
        "n_views": len(config.views) if config.images else 0,
        "resolution": config.resolution,
        "labels": config.labels,
        "k_shot": config.k_shot,
        "few_shot_seed": config.few_shot_seed,
        "object_list": config.object_list,
        "images": config.images,
        "scene_as_text": config.scene_as_text,
        "constrained": config.generation.constrained,
        "temperature": config.generation.temperature,
        "max_new_tokens": config.generation.max_new_tokens,
        "loc_alignment": config.scoring.loc_alignment,
        "execute": config.execute,
        "uav_noise": config.uav_noise,
        "benchmark_version": config.benchmark_version,
        "config_hash": manifest.config_hash[:8],
        "git_revision": manifest.git_revision or "",
        "protocol": manifest_protocol(manifest).name,
    }


def first_move(steps: Sequence[dict[str, Any]] | None) -> str | None:
    """The first horizontal UAV direction of a plan in the paper's JSON format."""
    for step in steps or ():
        if step.get("tasktype") == "UAV" and step.get("direction") in _HORIZONTAL:
            return str(step["direction"])
    return None


def _derived(record: EpisodeRecord) -> dict[str, Any]:
    return {
        "first_move": first_move(record.gt_plan),
        "pred_first_move": first_move(record.plan),
        "gt_steps": len(record.gt_plan),
        "pred_steps": record.parse.n_steps if record.parse is not None else None,
        "repairs": ",".join(record.parse.repairs) if record.parse is not None else "",
    }


def _run_frame(path: Path, label: str, manifest: RunManifest) -> pd.DataFrame:
    paths = RunPaths(path)
    records = latest_records(paths.records)
    # Records carry the run id of the folder they were written in; a copied or renamed folder
    # keeps them, so the settings are keyed by the records' ids.
    ids = {r.run_id for r in records}
    frame = records_frame(
        records,
        dict.fromkeys(ids, manifest.config.execute),
        dict.fromkeys(ids, manifest.config.scoring),
    )
    extra = pd.DataFrame([_derived(r) for r in records], index=frame.index)
    if extra.empty:
        extra = pd.DataFrame(columns=list(DERIVED[3:]), index=frame.index)
    settings = settings_of(manifest)
    for name in SETTINGS:
        frame[name] = [settings[name]] * len(frame)
    frame.insert(0, "run", label)
    frame.insert(1, "run_dir", str(path))
    return pd.concat([frame, extra], axis=1)


def load(*runs: str | Path, mixed_versions: bool = False) -> pd.DataFrame:
    """One row per episode of the given run folders (the latest record of each episode).

    Args:
        *runs: Run folders or glob patterns (``results/*``).
        mixed_versions: Accept runs of different benchmark versions (their scores are not
            comparable; the ``benchmark_version`` column tells them apart).

    Returns:
        The columns of :data:`vlm_bench.report.dataframe.COLUMNS`, then :data:`SETTINGS` and
        :data:`DERIVED` (``run`` and ``run_dir`` come first).

    Raises:
        ConfigError: A missing folder, or one that is no run.
        DataFileError: A corrupted manifest or ``records.jsonl`` (names the file and line).
        BenchmarkVersionError: Runs of different benchmark versions, unless ``mixed_versions``
            (names every run and its version).
    """
    paths = resolve_runs(runs)
    labels = run_labels(paths)
    manifests = [read_manifest(RunPaths(p)) for p in paths]
    if not mixed_versions:
        versions = [m.config.benchmark_version for m in manifests]
        check_one_version(list(zip(labels, versions, strict=True)), hint=MIXED_VERSIONS_HINT)
    frames = [_run_frame(*run) for run in zip(paths, labels, manifests, strict=True)]
    frame = pd.concat(frames, ignore_index=True)
    frame["paper_column"] = frame["task_id"].map(paper_grouping().task_map or {})
    return frame
