"""Episode records as a pandas DataFrame: one row per episode of each run, read from results/."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.floors import blind_s_loc
from vlm_bench.storage import NotARunError, RunPaths, latest_records, read_manifest
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.scores import PlanScores, ScoringConfig

DEFAULT = ScoringConfig()

METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total")
"""Score columns, in the paper's order (Plan, Loc, Obj, Skill, Tot); Succ follows."""

EXEC_METRICS = ("exec_success", "S_task", "S_pos", "S_arm", "S_safe", "VLA_total")
"""Execution columns (docs/design.md#execution-metrics): success, sub-goal completion and the
paper's VLA metrics. Missing (<NA>/NaN) for runs that do not execute plans and for backend
errors; False/0 for an answered episode of an executing run whose output held no plan."""

PADDING = ("Move_ratio", "S_loc_prec")
"""S_loc's padding diagnostics (floats; see :data:`COLUMNS`)."""

NO_PLAN = "no_plan"
"""``exec_failure_code`` of an answered episode of an executing run with no plan to execute
(the other codes are :class:`~vlm_bench.types.execution.FailureCode` values)."""

COLUMNS = (
    "run_id",
    "model",
    "key",
    "task_id",
    "suite",
    "seed",
    "instruction",
    "status",
    "tier",
    *METRICS,
    "Succ",
    "S_loc_blind",
    "Loc_over_blind",
    *PADDING,
    "first_target_visible",
    *EXEC_METRICS,
    "exec_failure",
    "exec_failure_code",
    "error_tags",
    "latency_s",
    "prompt_tokens",
    "completion_tokens",
    "backend_error",
)
"""Columns of :func:`records_frame`, in order.

Types: the scores (``S_*``, ``VLA_total``, 0-100) are floats; the per-episode outcomes ``Succ``
and ``exec_success`` are nullable booleans (True/False/<NA>), which the tables turn into
percentages of episodes; ``error_tags`` is a list of strings; the token counts are nullable
integers (``Int64``, <NA> where the backend did not say). ``Move_ratio`` (predicted UAV steps /
GT moves) and ``S_loc_prec`` (S_loc's credits over the larger of the two) show padding beside
S_loc (docs/metrics.md#padding); both are NaN in records from before version 3, which lack
the count, and ``Move_ratio`` where the GT has no move."""
OUTCOMES = ("Succ", "exec_success")
"""Per-episode outcomes: nullable booleans in the frame, percentages in the tables."""
RECOVERED = "Recovered"
"""Closed loop: the episode failed round 0 and succeeded in a later one (nullable boolean;
<NA> where round 0 succeeded or the run is open-loop); its mean is the recovery rate."""


def succ_at_column(k: int) -> str:
    """Closed loop: the column of Succ@k (the task succeeded within rounds 0..k; a nullable
    boolean, <NA> for open-loop runs). Succ@0 is round 0's ``exec_success``."""
    return f"Succ@{k}"


def loop_columns(columns: Iterable[str]) -> tuple[str, ...]:
    """The closed-loop columns among ``columns``: Succ@1..K (Succ@0 is ``exec_success``) and
    :data:`RECOVERED`, in that order."""
    names = set(columns)
    ks = sorted(int(c.split("@", 1)[1]) for c in names if c.startswith("Succ@") and c[5:].isdigit())
    found = tuple(succ_at_column(k) for k in ks if k > 0)
    return (*found, RECOVERED) if found and RECOVERED in names else found


TOKENS = ("prompt_tokens", "completion_tokens")


def _exec_values(record: EpisodeRecord, executed: bool) -> dict[str, object]:
    if not executed or not record.ok:
        return {
            **dict.fromkeys(EXEC_METRICS, math.nan),
            "exec_failure": None,
            "exec_failure_code": None,
        }
    run = record.execution
    if run is None:
        return {
            **dict.fromkeys(EXEC_METRICS, 0.0),
            "exec_success": False,
            "exec_failure": "not executed (no plan)",
            "exec_failure_code": NO_PLAN,
        }
    vla = run.scores
    return {
        "exec_success": run.exec_success,
        "S_task": run.s_task,
        "S_pos": vla.s_pos if vla else 0.0,
        "S_arm": vla.s_arm if vla else 0.0,
        "S_safe": vla.s_safe if vla else 0.0,
        "VLA_total": vla.total if vla else 0.0,
        "exec_failure": run.failure_reason,
        "exec_failure_code": None if run.failure_code is None else run.failure_code.value,
    }


def _padding_values(scores: PlanScores | None) -> dict[str, float | None]:
    """``Move_ratio`` and ``S_loc_prec`` of one record (see :data:`COLUMNS`)."""
    if scores is None:
        return {"Move_ratio": None, "S_loc_prec": None}
    if "s_loc_precision" not in scores.model_fields_set:  # written before version 3
        return {"Move_ratio": math.nan, "S_loc_prec": math.nan}
    ratio = scores.n_move_pred / scores.n_move if scores.n_move else math.nan
    return {"Move_ratio": ratio, "S_loc_prec": scores.s_loc_precision}


def _loop_values(record: EpisodeRecord) -> dict[str, object]:
    loop = record.loop
    if loop is None or not record.ok:
        return {}
    values: dict[str, object] = {succ_at_column(k): ok for k, ok in enumerate(loop.succ_at)}
    values[RECOVERED] = None if loop.succ_at[0] else loop.recovered
    return values


def _row(record: EpisodeRecord, executed: bool, scoring: ScoringConfig) -> dict[str, object]:
    scores = record.scores
    floor = blind_s_loc(record, scoring) if scores else None
    return {
        "run_id": record.run_id,
        "model": record.model,
        "key": record.key,
        "task_id": record.task_id,
        "suite": record.suite.value,
        "seed": record.seed,
        "instruction": record.variant,
        "status": record.status,
        "tier": record.parse.tier if record.parse is not None else None,
        "S_plan": scores.s_plan if scores else None,
        "S_loc": scores.s_loc if scores else None,
        "S_obj": scores.s_obj if scores else None,
        "S_skill": scores.s_skill if scores else None,
        "S_total": scores.s_total if scores else None,
        "Succ": scores.succ if scores else None,
        "S_loc_blind": floor,
        "Loc_over_blind": scores.s_loc - floor if scores and floor is not None else None,
        **_padding_values(scores),
        "first_target_visible": record.first_target_visible,
        **_exec_values(record, executed),
        "error_tags": list(record.error_tags),
        "latency_s": record.latency_s,
        "prompt_tokens": record.prompt_tokens,
        "completion_tokens": record.completion_tokens,
        "backend_error": record.backend_error,
        **_loop_values(record),
    }


def executing_runs(records: Iterable[EpisodeRecord]) -> dict[str, bool]:
    """Guess which runs executed plans: those with at least one executed record."""
    out: dict[str, bool] = {}
    for record in records:
        out[record.run_id] = out.get(record.run_id, False) or record.execution is not None
    return out


def records_frame(
    records: Iterable[EpisodeRecord],
    executed: Mapping[str, bool] | None = None,
    scoring: Mapping[str, ScoringConfig] | None = None,
) -> pd.DataFrame:
    """One row per record with the columns of :data:`COLUMNS`.

    Args:
        records: Episode records of one or more runs.
        executed: Whether each run (by run id) executes plans, from its manifest's
            ``config.execute``; runs missing there are guessed by :func:`executing_runs`.
        scoring: Each run's scoring options (by run id), for the ``blind`` floor's S_loc
            (``S_loc_blind``, see :mod:`vlm_bench.report.floors`); default options otherwise.

    Score columns are NaN (and ``Succ`` is None) for records whose backend failed
    (``status == "error"``); see :data:`EXEC_METRICS` for the execution columns. Where some
    run is closed-loop, ``Succ@0``..``Succ@K`` (:func:`succ_at_column`) and :data:`RECOVERED`
    follow.
    """
    records = list(records)
    runs = {**executing_runs(records), **(executed or {})}
    options = scoring or {}
    rows = [_row(r, runs[r.run_id], options.get(r.run_id, DEFAULT)) for r in records]
    rounds = max((len(r.loop.succ_at) for r in records if r.loop is not None), default=0)
    loops = [succ_at_column(k) for k in range(rounds)] + ([RECOVERED] if rounds else [])
    frame = pd.DataFrame(rows, columns=[*COLUMNS, *loops])
    for col in (*METRICS, "S_loc_blind", "Loc_over_blind", *PADDING, *EXEC_METRICS):
        if col not in OUTCOMES:
            frame[col] = frame[col].astype(float)
    for col in (*OUTCOMES, *loops):
        frame[col] = frame[col].astype("boolean")
    for col in TOKENS:
        frame[col] = frame[col].astype("Int64")
    return frame


def csv_ready(frame: pd.DataFrame) -> pd.DataFrame:
    """``frame`` for a CSV file: ``error_tags`` joined by commas (Parquet keeps the lists)."""
    if "error_tags" not in frame.columns:
        return frame
    return frame.assign(error_tags=frame["error_tags"].map(",".join))


def load_records_frame(runs: Path | str | Sequence[Path | str]) -> pd.DataFrame:
    """The records of one or more run folders (the latest record of each episode).

    Whether a run executes plans comes from its manifest (guessed from the records when the
    folder has none).

    Raises:
        DataFileError: A corrupted ``records.jsonl`` or manifest (names the file and line).
    """
    roots = [runs] if isinstance(runs, Path | str) else list(runs)
    records: list[EpisodeRecord] = []
    executed: dict[str, bool] = {}
    scoring: dict[str, ScoringConfig] = {}
    for root in roots:
        paths = RunPaths(Path(root))
        records.extend(latest_records(paths.records))
        try:
            manifest = read_manifest(paths)
        except NotARunError:
            continue
        executed[manifest.run_id] = manifest.config.execute
        scoring[manifest.run_id] = manifest.config.scoring
    return records_frame(records, executed, scoring)
