"""Build, write and read a run's ``results.json`` (:class:`~vlm_bench.types.results.RunResults`).

The values are the run's summary table (:mod:`vlm_bench.report.summary`) with the report's
task-clustered bootstrap intervals (:mod:`vlm_bench.report.bootstrap`), and Succ@k of a closed
loop run (:mod:`vlm_bench.report.closed_loop`): the numbers ``vlm-bench report --stats`` shows.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, cast

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from pydantic import ValidationError

from vlm_bench.catalog.model_cards import card_of
from vlm_bench.errors import DataFileError
from vlm_bench.report.bootstrap import CI_METRICS, bootstrap_cis
from vlm_bench.report.closed_loop import loop_frame, succ_at_k
from vlm_bench.report.groups import OVERALL, SUITES
from vlm_bench.report.load import load
from vlm_bench.report.report_options import BOOT_SEED, CI_LEVEL, N_BOOT
from vlm_bench.report.summary import BOTH, MISSING, summary_long
from vlm_bench.storage import RunPaths, read_manifest
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.protocol_match import manifest_protocol
from vlm_bench.types.records import utc_now
from vlm_bench.types.results import (
    RESULTS_FILE,
    Counts,
    Estimate,
    GroupResults,
    InstructionName,
    InstructionResults,
    Intervals,
    ModelInfo,
    RunResults,
    SuccAtK,
)

EXEC_CI_METRICS = ("exec_success", "S_task")
"""Execution metrics of results.json (when plans were executed)."""
EXTRA_METRICS = ("Move_ratio", "S_loc_prec")
"""Episode columns included when the release's frame has them."""


def _number(value: Any) -> float | None:
    if value is None or pd.isna(value):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def _estimate(row: pd.Series) -> Estimate:
    return Estimate(value=_number(row["value"]), lo=_number(row["lo"]), hi=_number(row["hi"]))


def _metrics(frame: pd.DataFrame) -> tuple[str, ...]:
    ok = frame[frame["status"] == "ok"]
    executed = "exec_success" in ok.columns and bool(ok["exec_success"].notna().any())
    extra = tuple(m for m in EXTRA_METRICS if m in frame.columns)
    return (*CI_METRICS, *(EXEC_CI_METRICS if executed else ()), *extra)


def _instruction_rows(frame: pd.DataFrame, n_boot: int, seed: int, level: float) -> list[Any]:
    cis = bootstrap_cis(frame, "model", SUITES, _metrics(frame), n_boot, seed, level)
    long = summary_long(frame, "model", SUITES)
    rows: list[InstructionResults] = []
    for instruction in ("explicit", "implicit", BOTH):
        mine = cis[cis["instruction"] == instruction]
        if mine.empty:
            continue
        groups = []
        for group in [*SUITES.order, OVERALL]:
            cells = mine[mine["suite"] == group]
            if cells.empty:
                continue
            table = long[(long["instruction"] == instruction) & (long["suite"] == group)]
            n = int(table["n"].iloc[0]) if not table.empty else int(cells["n"].max())
            missing = str(table[MISSING].iloc[0]) if not table.empty else ""
            groups.append(
                GroupResults(
                    group=group,
                    n=n,
                    complete=not missing,
                    metrics={str(r["metric"]): _estimate(r) for _, r in cells.iterrows()},
                )
            )
        rows.append(
            InstructionResults(instruction=cast(InstructionName, instruction), groups=groups)
        )
    return rows


def _succ_at_k(frame: pd.DataFrame, n_boot: int, seed: int, level: float) -> list[SuccAtK]:
    loops = loop_frame(frame)
    if loops.empty:
        return []
    pooled = loops.assign(instruction=BOTH)
    curve = pd.concat(
        [succ_at_k(loops, n_boot, seed, level), succ_at_k(pooled, n_boot, seed, level)],
        ignore_index=True,
    )
    return [
        SuccAtK(
            instruction=cast(InstructionName, r["instruction"]),
            k=int(r["k"]),
            estimate=_estimate(r),
            n=int(r["n"]),
        )
        for _, r in curve.iterrows()
    ]


def build_results(
    run_dir: Path | str, n_boot: int = N_BOOT, seed: int = BOOT_SEED, level: float = CI_LEVEL
) -> RunResults:
    """The ``results.json`` content of a run folder, from its manifest and records.

    Raises:
        ConfigError: Not a run folder. DataFileError: A corrupted manifest or records file.
    """
    paths = RunPaths(Path(run_dir))
    manifest = read_manifest(paths)
    frame = load(paths.root)
    ok = frame[frame["status"] == "ok"]
    card = card_of(manifest.config.model)
    counts = Counts(
        episodes=len(frame),
        answered=len(ok),
        errors=int((frame["status"] != "ok").sum()),
        executed=int(ok["exec_success"].notna().sum()) if "exec_success" in ok else 0,
    )
    return RunResults(
        benchmark_version=manifest.config.benchmark_version,
        package_version=manifest.packages.get("vlm-bench", ""),
        packages=manifest.packages,
        run_id=manifest.run_id,
        written=utc_now(),
        model=ModelInfo(
            name=manifest.config.model,
            backend=manifest.backend,
            card=card.model_dump(mode="json") if card is not None else None,
        ),
        protocol=manifest_protocol(manifest),
        config_hash=manifest.config_hash,
        config=manifest.config.model_dump(mode="json"),
        loop=manifest.config.loop,
        counts=counts,
        results=_instruction_rows(frame, n_boot, seed, level) if len(ok) else [],
        succ_at_k=_succ_at_k(frame, n_boot, seed, level),
        intervals=Intervals(n_boot=n_boot, level=level, seed=seed),
    )


def write_results(run_dir: Path | str) -> Path:
    """Write ``results.json`` into the run folder (atomically); returns its path."""
    results = build_results(run_dir)
    path = Path(run_dir) / RESULTS_FILE
    write_text_atomic(path, results.model_dump_json(indent=1) + "\n")
    return path


def read_results(path: Path | str) -> RunResults:
    """Read a ``results.json`` file (a run folder's or one on its own).

    Raises:
        DataFileError: Not readable, not JSON, or not a results file of a known version (names
            the file and the first wrong field).
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise DataFileError(str(path), f"cannot read results: {exc}") from None
    try:
        return RunResults.model_validate(data)
    except ValidationError as exc:
        problem = exc.errors()[0]
        where = ".".join(str(p) for p in problem["loc"])
        raise DataFileError(str(path), f"not a results.json: {where}: {problem['msg']}") from None
