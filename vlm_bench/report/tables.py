"""Render the summary: Markdown and rich tables in the paper layout, CSV in long form."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from rich import box
from rich.table import Table

from vlm_bench.report.dataframe import load_records_frame, loop_columns
from vlm_bench.report.groups import OVERALL, SUITES, Grouping
from vlm_bench.report.marks import PARTIAL, cell_text, partial_warnings, row_texts
from vlm_bench.report.summary import (
    DIAGNOSTICS,
    VALUES,
    By,
    by_columns,
    exec_coverage,
    partial_overalls,
    summary_long,
    summary_wide,
    table_values,
)
from vlm_bench.storage import NotARunError, RunPaths, read_manifest
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.protocol_match import manifest_protocol

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
    "Recovered": "Rec",
    "Move_ratio": "Mv/GT",
    "S_loc_prec": "LocP",
}
"""Metric column headers as in the paper (Exec = execution success, Task = S_task; closed
loop: Succ@k as named, Rec = recovered share of round-0 failures)."""


def header(metric: str) -> str:
    """The column header of ``metric`` (:data:`HEADERS`; other columns by their name)."""
    return HEADERS.get(metric, metric)


LEGEND = (
    "Succ in %; ΔLoc = Loc minus the blind floor's Loc on the same episodes (what the images "
    "add); Overall = unweighted mean of the {groups} columns; `both` = mean of explicit "
    "and implicit; episodes whose backend failed are excluded (see summary.csv n_error)."
)
EXEC_LEGEND = (
    "Exec = execution success in % and Task = S_task (sub-goals done), over answered "
    "episodes, an output with no plan counting 0; summary.csv adds S_pos, S_arm, "
    "S_safe and VLA_total."
)
DIAGNOSTIC_LEGEND = (
    "Diagnostics, not the paper's metrics: Mv/GT = predicted UAV moves over the GT plan's "
    "(mean ratio); LocP = S_loc that also charges extra moves (precision-aware)."
)
LOOP_LEGEND = (
    "Closed loop: Succ@k = task success within k replans in % (Succ@0 = Exec); Rec = share of "
    "the episodes that failed round 0 that a later round recovered, in %."
)
COVERAGE_LEGEND = (
    "Exec and Task with (e/n) cover only the e of the cell's n answered episodes that were "
    "executed (the others come from runs that do not execute plans)."
)


def _groups(wide: pd.DataFrame) -> list[str]:
    return list(dict.fromkeys(col[0] for col in wide.columns))


def _metrics(wide: pd.DataFrame) -> list[str]:
    return list(dict.fromkeys(col[1] for col in wide.columns))


def _header_names(grouping: Grouping, groups: list[str], metrics: list[str]) -> list[str]:
    return [f"{grouping.short[g]} {header(m)}" for g in groups for m in metrics]


def system_headers(by: By) -> list[str]:
    """Row-label headers: ``Model`` for the model column, else the column names."""
    return ["Model" if b == "model" else b for b in by_columns(by)]


def group_legend(grouping: Grouping, groups: Sequence[str]) -> str:
    """``BM = Base Manipulation, LH = Long-Horizon`` for the groups shown."""
    return ", ".join(f"{grouping.short[g]} = {grouping.titles[g]}" for g in groups if g != OVERALL)


def summary_markdown(long: pd.DataFrame, by: By = "model", grouping: Grouping = SUITES) -> str:
    """The paper-layout table as GitHub Markdown, with a legend of the group abbreviations."""
    wide = summary_wide(long, by, grouping)
    if wide.empty:
        return "_No episodes._\n"
    groups, metrics = _groups(wide), _metrics(wide)
    head = [*system_headers(by), "Instr.", *_header_names(grouping, groups, metrics)]
    labels = len(by_columns(by)) + 1
    lines = [
        "| " + " | ".join(head) + " |",
        "|" + "|".join([":--"] * labels + ["--:"] * (len(head) - labels)) + "|",
    ]
    partial, coverage = partial_overalls(long, by), exec_coverage(long, by, grouping)
    for key in wide.index:
        cells = [*(str(k) for k in key), *row_texts(wide, key, partial, coverage)]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    overall = long[long[grouping.column] == OVERALL]
    n = int(overall[overall["instruction"] != "both"]["n"].sum())
    legend = LEGEND.format(groups="suite" if grouping.name == "suites" else "paper's")
    legend = f"{legend} {EXEC_LEGEND}" if "exec_success" in metrics else legend
    legend = f"{legend} {LOOP_LEGEND}" if loop_columns(metrics) else legend
    legend = f"{legend} {DIAGNOSTIC_LEGEND}" if set(DIAGNOSTICS) & set(metrics) else legend
    legend = f"{legend} {COVERAGE_LEGEND}" if exec_coverage(long, by, grouping) else legend
    names = group_legend(grouping, groups)
    warnings = "".join(f"\n**Warning.** {w}\n" for w in partial_warnings(long, by, grouping))
    return "\n".join(lines) + f"\n\n{names}. {legend} Episodes scored: {n}.\n" + warnings


def _caption(metrics: Sequence[str], covered: bool = False) -> str:
    caption = "Succ in %; Overall = mean of the column groups"
    if "exec_success" in metrics:
        caption += "; Exec = execution success in %, Task = S_task"
    if loop_columns(metrics):
        caption += "; Succ@k = success within k replans, Rec = recovered failures (%)"
    if set(DIAGNOSTICS) & set(metrics):
        caption += "; diagnostics: Mv/GT = predicted/GT UAV moves, LocP = precision-aware Loc"
    if covered:
        caption += "; (e/n) = executed e of n episodes"
    return caption


def _warned(caption: str, long: pd.DataFrame, by: By, grouping: Grouping) -> str:
    warnings = partial_warnings(long, by, grouping)
    return caption + "".join(f"\n[yellow]{w}[/]" for w in warnings)


def _rich_wide(
    wide: pd.DataFrame, long: pd.DataFrame, by: By, grouping: Grouping, title: str | None
) -> Table:
    metrics = _metrics(wide)
    groups = _groups(wide)
    covered = bool(exec_coverage(long, by, grouping))
    caption = f"{group_legend(grouping, groups)}; {_caption(metrics, covered)}"
    caption = _warned(caption, long, by, grouping)
    table = Table(title=title, caption=caption)
    for name in system_headers(by):
        table.add_column(name, no_wrap=True)
    table.add_column("Instr.")
    for group in groups:
        for metric in metrics:
            label = f"{grouping.short[group]}\n{header(metric)}"
            table.add_column(
                f"[bold]{label}[/]" if metric == "S_total" else label, justify="right", no_wrap=True
            )
    partial, coverage = partial_overalls(long, by), exec_coverage(long, by, grouping)
    for key in wide.index:
        table.add_row(*(str(k) for k in key), *row_texts(wide, key, partial, coverage))
    return table


def _rich_long(
    long: pd.DataFrame, by: By, grouping: Grouping, title: str | None, short: bool
) -> Table:
    keys = by_columns(by)
    metrics = table_values(long)
    caption = _caption(metrics, bool(exec_coverage(long, by, grouping)))
    if short:
        present = [g for g in grouping.order if g in set(long[grouping.column])]
        caption = f"{group_legend(grouping, present)}; {caption}"
    caption = _warned(caption, long, by, grouping)
    partial, coverage = partial_overalls(long, by), exec_coverage(long, by, grouping)
    # Eight metric columns (with execution) fit 80 characters only with the box's one-space
    # column separators and no padding.
    padding = (0, 0) if len(metrics) > len(VALUES) else (0, 1)
    table = Table(
        title=title, caption=caption, box=box.SIMPLE_HEAD, collapse_padding=True, padding=padding
    )
    for name in system_headers(by):
        table.add_column(name, overflow="fold")
    table.add_column("Instr.", no_wrap=True, min_width=8)  # "explicit" in full
    table.add_column("Suite" if grouping.name == "suites" else "Column", no_wrap=True)
    for metric in metrics:
        bold = metric == "S_total"
        table.add_column(
            f"[bold]{header(metric)}[/]" if bold else header(metric),
            justify="right",
            no_wrap=True,
        )
    table.add_column("n", justify="right")
    previous = None
    for _, row in long.iterrows():
        group = (*(row[k] for k in keys), row["instruction"])
        value = row[grouping.column]
        overall = value == OVERALL
        name = grouping.short[value] if short or overall else grouping.titles[value]
        bold = overall and group not in partial
        if overall and not bold:
            name += PARTIAL
        first = group != previous
        cells = [
            *(str(row[k]) if first else "" for k in keys),
            str(row["instruction"]) if first else "",
            name,
            *(cell_text(row[m], m, (*group, value), coverage) for m in metrics),
            str(row["n"]),
        ]
        table.add_row(*cells, style="bold" if bold else None, end_section=overall)
        previous = group
    return table


def summary_rich(
    long: pd.DataFrame,
    by: By = "model",
    title: str | None = None,
    width: int | None = None,
    grouping: Grouping = SUITES,
) -> Table:
    """The summary for the terminal.

    The paper layout (rows system × instruction, group × metric columns) when it fits in
    ``width`` characters (None = always); otherwise one row per system × instruction × group.
    """
    wide = summary_wide(long, by, grouping)
    if wide.empty:
        return _rich_long(long, by, grouping, title, short=False)
    keys = by_columns(by)
    name = sum(max(len(str(s)) for s in long[k]) + 3 for k in keys)
    if width is None or 21 + name + 8 * len(wide.columns) <= width:
        return _rich_wide(wide, long, by, grouping, title)
    short = name + 55 + 7 * len(table_values(long)) > width
    return _rich_long(long, by, grouping, title, short=short)


def write_summary(run_dir: Path, by: str = "model") -> pd.DataFrame:
    """Write ``summary.md`` and ``summary.csv`` of a run folder from its records, each with the
    run's protocol (a ``protocol`` column last in the CSV).

    Returns:
        The long summary (:func:`vlm_bench.report.summary.summary_long`).
    """
    paths = RunPaths(run_dir)
    long = summary_long(load_records_frame(run_dir), by)
    try:
        protocol: str | None = manifest_protocol(read_manifest(paths)).label()
    except NotARunError:  # records without a manifest: no protocol to state
        protocol = None
    head = f"# {paths.run_id}\n\n"
    if protocol is not None:
        head += f"Protocol: {protocol} (docs/protocols.md).\n\n"
    write_text_atomic(paths.summary_md, head + summary_markdown(long, by))
    shown = long if protocol is None else long.assign(protocol=protocol)
    csv = shown.to_csv(index=False, float_format="%.4f")
    write_text_atomic(paths.summary_csv, csv)
    return long
