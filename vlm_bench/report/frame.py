"""Episode records as a pandas DataFrame: one row per episode of each run, read from results/."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.storage import RunPaths, latest_records
from vlm_bench.types.records import EpisodeRecord

METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total")
"""Score columns, in the paper's order (Plan, Loc, Obj, Skill, Tot); Succ follows."""

COLUMNS = (
    "run_id", "model", "key", "task_id", "suite", "seed", "instruction", "status", "tier",
    *METRICS, "Succ", "error_tags", "latency_s", "prompt_tokens", "completion_tokens",
    "backend_error",
)
"""Columns of :func:`records_frame`, in order."""


def _row(record: EpisodeRecord) -> dict[str, object]:
    scores = record.scores
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
        "error_tags": ",".join(record.error_tags),
        "latency_s": record.latency_s,
        "prompt_tokens": record.prompt_tokens,
        "completion_tokens": record.completion_tokens,
        "backend_error": record.backend_error,
    }


def records_frame(records: Iterable[EpisodeRecord]) -> pd.DataFrame:
    """One row per record with the columns of :data:`COLUMNS`.

    Score columns are NaN (and ``Succ`` is None) for records whose backend failed
    (``status == "error"``).
    """
    rows = [_row(r) for r in records]
    frame = pd.DataFrame(rows, columns=list(COLUMNS))
    for col in METRICS:
        frame[col] = frame[col].astype(float)
    return frame


def load_records_frame(runs: Path | str | Sequence[Path | str]) -> pd.DataFrame:
    """The records of one or more run folders (the latest record of each episode).

    Raises:
        DataFileError: A corrupted ``records.jsonl`` (names the file and line).
    """
    roots = [runs] if isinstance(runs, Path | str) else list(runs)
    records: list[EpisodeRecord] = []
    for root in roots:
        records.extend(latest_records(RunPaths(Path(root)).records))
    return records_frame(records)
