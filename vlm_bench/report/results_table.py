"""The summary table of ``results.json`` files on their own (no records beside them): what a
leaderboard holds. ``vlm-bench report a/results.json b/results.json`` prints it.

Rows are the files' own values, in :func:`~vlm_bench.report.summary.summary_long`'s layout with
one system per file (``run`` = its run id, made unique) and its ``protocol`` beside it; runs of
different protocols are never shown without the warning of :func:`protocol_warnings`.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import ConfigError
from vlm_bench.report.groups import OVERALL
from vlm_bench.report.results_file import read_results
from vlm_bench.report.summary import MISSING
from vlm_bench.report.tables import summary_markdown
from vlm_bench.storage import RunPaths
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.results import RESULTS_FILE, RunResults

TABLE_METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ")
EXEC_METRICS = ("exec_success", "S_task")


def standalone_results(patterns: Sequence[str | Path]) -> list[Path]:
    """The given paths that are ``results.json`` files with no run folder around them.

    Raises:
        ConfigError: Such files mixed with run folders (one table needs one source).
    """
    files = [
        Path(p)
        for p in patterns
        if Path(p).is_file()
        and Path(p).suffix == ".json"
        and not RunPaths(Path(p).parent).manifest.exists()
    ]
    if files and len(files) != len(patterns):
        raise ConfigError(
            f"give run folders or {RESULTS_FILE} files on their own, not both (e.g. {files[0]})"
        )
    return files


def results_long(results: Sequence[RunResults]) -> pd.DataFrame:
    """One row per file × instruction × suite (overall included) with the table's values."""
    rows = []
    names = [r.run_id for r in results]
    for n, result in enumerate(results):
        run = result.run_id if names.count(result.run_id) == 1 else f"{result.run_id}#{n + 1}"
        executed = result.counts.executed > 0
        for row in result.results:
            for group in row.groups:
                values = {m: e.value for m, e in group.metrics.items()}
                missing = "" if group.complete or group.group != OVERALL else "some"
                rows.append(
                    {
                        "run": run,
                        "model": result.model.name,
                        "protocol": result.protocol.label(),
                        "instruction": row.instruction,
                        "suite": group.group,
                        **{m: values.get(m) for m in TABLE_METRICS},
                        "Loc_over_blind": float("nan"),
                        **({m: values.get(m) for m in EXEC_METRICS} if executed else {}),
                        "n": group.n,
                        "n_error": result.counts.errors if group.group == OVERALL else 0,
                        MISSING: missing,
                    }
                )
    return pd.DataFrame(rows)


def protocol_warnings(long: pd.DataFrame) -> list[str]:
    """A warning when the rows come from runs of more than one protocol."""
    if long.empty or "protocol" not in long.columns:
        return []
    by_protocol = long.drop_duplicates("run").groupby("protocol", sort=False)["run"]
    if by_protocol.ngroups < 2:
        return []
    parts = "; ".join(f"{p}: {', '.join(runs)}" for p, runs in by_protocol)
    return [f"Runs of different protocols ({parts}): their numbers are not comparable."]


def read_standalone(paths: Sequence[Path]) -> pd.DataFrame:
    """:func:`results_long` of the files (read and validated)."""
    return results_long([read_results(p) for p in paths])


def print_results_files(paths: Sequence[Path], fmt: str, out: Path | None) -> None:
    """``vlm-bench report`` on ``results.json`` files: their table as Markdown (``terminal``
    and ``markdown``) or CSV, each row with its protocol; warnings on stderr.

    Raises:
        ConfigError: Another format (the statistics need the records).
    """
    import sys

    if fmt not in ("terminal", "markdown", "csv"):
        raise ConfigError(
            f"results.json files give terminal, markdown or csv tables, not {fmt!r} (the other "
            "formats need the run folders' records)"
        )
    long = read_standalone(paths)
    if fmt == "csv":
        text = long.to_csv(index=False, float_format="%.4f")
    else:
        text = "# vlm-bench results\n\n" + summary_markdown(long, ["run", "protocol"])
    if out is not None:
        write_text_atomic(out, text)
        print(f"wrote {out}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    for warning in protocol_warnings(long):
        print(f"warning: {warning}", file=sys.stderr)
