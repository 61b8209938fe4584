"""Render the summary: Markdown and rich tables in the paper layout, CSV in long form."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from rich import box
from rich.table import Table

from vlm_bench.report.frame import load_records_frame
from vlm_bench.report.summary import (
    OVERALL,
    SUITE_ORDER,
    VALUES,
    summary_long,
    summary_wide,
    table_values,
)
from vlm_bench.storage import RunPaths
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.task import Suite

HEADERS = {
    "S_plan": "Plan",
    "S_loc": "Loc",
    "S_obj": "Obj",
    "S_skill": "Skill",
    "S_total": "Tot",
    "Succ": "Succ",
    "Loc_over_blind": "ΔLoc",
    "exec_success": "Exec",
    "S_task": "Task",
}
"""Metric column headers as in the paper (Exec = execution success, Task = S_task)."""
SUITE_SHORT = {
    Suite.BASE.value: "BM",
    Suite.OBJECT_SPATIAL.value: "OS",
    Suite.SEMANTIC.value: "SU",
    Suite.LONG_HORIZON.value: "LH",
    OVERALL: "Overall",
}
"""Short suite names for column headers."""

LEGEND = (
    "Succ in %; ΔLoc = Loc minus the blind floor's Loc on the same episodes (what the images "
    "add); Overall = unweighted mean of the suite columns; `both` = mean of explicit "
    "and implicit; episodes whose backend failed are excluded (see summary.csv n_error)."
)
EXEC_LEGEND = (
    "Exec = execution success in % and Task = S_task (sub-goals done), over answered "
    "episodes, an output with no plan counting 0; summary.csv adds S_pos, S_arm, "
    "S_safe and VLA_total."
)


def _fmt(value: object) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    return f"{float(value):.1f}"  # type: ignore[arg-type]


def _suites(wide: pd.DataFrame) -> list[str]:
    return list(dict.fromkeys(col[0] for col in wide.columns))


def _metrics(wide: pd.DataFrame) -> list[str]:
    return list(dict.fromkeys(col[1] for col in wide.columns))


def _header_names(suites: list[str], metrics: list[str]) -> list[str]:
    return [f"{SUITE_SHORT[s]} {HEADERS[m]}" for s in suites for m in metrics]


def summary_markdown(long: pd.DataFrame, by: str = "model") -> str:
    """The paper-layout table as GitHub Markdown, with a legend of the suite abbreviations."""
    wide = summary_wide(long, by)
    if wide.empty:
        return "_No episodes._\n"
    suites, metrics = _suites(wide), _metrics(wide)
    head = ["Model" if by == "model" else by, "Instr.", *_header_names(suites, metrics)]
    lines = [
        "| " + " | ".join(head) + " |",
        "|" + "|".join([":--", ":--"] + ["--:"] * (len(head) - 2)) + "|",
    ]
    for (system, instruction), row in wide.iterrows():
        cells = [str(system), str(instruction), *(_fmt(v) for v in row.tolist())]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    names = ", ".join(f"{SUITE_SHORT[s]} = {Suite(s).label}" for s in suites if s in SUITE_ORDER)
    counts = long[long["suite"] == OVERALL]
    n = int(counts[counts["instruction"] != "both"]["n"].sum())
    legend = f"{LEGEND} {EXEC_LEGEND}" if "exec_success" in metrics else LEGEND
    return "\n".join(lines) + f"\n\n{names}. {legend} Episodes scored: {n}.\n"


def _caption(metrics: Sequence[str]) -> str:
    caption = "Succ in %; Overall = mean of suites"
    if "exec_success" in metrics:
        caption += "; Exec = execution success in %, Task = S_task"
    return caption


def _rich_wide(wide: pd.DataFrame, by: str, title: str | None) -> Table:
    metrics = _metrics(wide)
    table = Table(title=title, caption=_caption(metrics))
    table.add_column("Model" if by == "model" else by, no_wrap=True)
    table.add_column("Instr.")
    for suite in _suites(wide):
        for metric in metrics:
            label = f"{SUITE_SHORT[suite]}\n{HEADERS[metric]}"
            table.add_column(
                f"[bold]{label}[/]" if metric == "S_total" else label, justify="right", no_wrap=True
            )
    for (system, instruction), row in wide.iterrows():
        table.add_row(str(system), str(instruction), *(_fmt(v) for v in row.tolist()))
    return table


def _rich_long(long: pd.DataFrame, by: str, title: str | None, short: bool) -> Table:
    metrics = table_values(long)
    caption = _caption(metrics)
    if short:
        present = [s for s in SUITE_ORDER if s in set(long["suite"])]
        legend = ", ".join(f"{SUITE_SHORT[s]} = {Suite(s).label}" for s in present)
        caption = f"{legend}; {caption}"
    # Eight metric columns (with execution) fit 80 characters only with the box's one-space
    # column separators and no padding.
    padding = (0, 0) if len(metrics) > len(VALUES) else (0, 1)
    table = Table(
        title=title, caption=caption, box=box.SIMPLE_HEAD, collapse_padding=True, padding=padding
    )
    table.add_column("Model" if by == "model" else by, overflow="fold")
    table.add_column("Instr.")
    table.add_column("Suite", no_wrap=True)
    for metric in metrics:
        bold = metric == "S_total"
        table.add_column(
            f"[bold]{HEADERS[metric]}[/]" if bold else HEADERS[metric],
            justify="right",
            no_wrap=True,
        )
    table.add_column("n", justify="right")
    previous = None
    for _, row in long.iterrows():
        group = (row[by], row["instruction"])
        overall = row["suite"] == OVERALL
        name = SUITE_SHORT[row["suite"]] if short or overall else Suite(row["suite"]).label
        cells = [
            str(row[by]) if group != previous else "",
            str(row["instruction"]) if group != previous else "",
            name,
            *(_fmt(row[m]) for m in metrics),
            str(row["n"]),
        ]
        table.add_row(*cells, style="bold" if overall else None, end_section=overall)
        previous = group
    return table


def summary_rich(
    long: pd.DataFrame, by: str = "model", title: str | None = None, width: int | None = None
) -> Table:
    """The summary for the terminal.

    The paper layout (rows system × instruction, suite × metric columns) when it fits in
    ``width`` characters (None = always); otherwise one row per system × instruction × suite.
    """
    wide = summary_wide(long, by)
    if wide.empty:
        return _rich_long(long, by, title, short=False)
    name = max(len(str(s)) for s in long[by])
    if width is None or 24 + name + 8 * len(wide.columns) <= width:
        return _rich_wide(wide, by, title)
    return _rich_long(long, by, title, short=name + 58 + 7 * len(table_values(long)) > width)


def write_summary(run_dir: Path, by: str = "model") -> pd.DataFrame:
    """Write ``summary.md`` and ``summary.csv`` of a run folder from its records.

    Returns:
        The long summary (:func:`vlm_bench.report.summary.summary_long`).
    """
    paths = RunPaths(run_dir)
    long = summary_long(load_records_frame(run_dir), by)
    write_text_atomic(paths.summary_md, f"# {paths.run_id}\n\n" + summary_markdown(long, by))
    write_text_atomic(paths.summary_csv, long.to_csv(index=False, float_format="%.4f"))
    return long
