"""What the tables mark beside their numbers, in every format: a partial Overall (a row that
misses groups of the table, :func:`~vlm_bench.report.summary.partial_overalls`) and execution
values over only some of a cell's episodes (:func:`~vlm_bench.report.summary.exec_coverage`)."""

from __future__ import annotations

import math

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.groups import OVERALL, Grouping
from vlm_bench.report.summary import TABLE_EXEC_VALUES, By, by_columns, partial_overalls


def fmt(value: object) -> str:
    """A table number with one decimal; – for a missing value."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    return f"{float(value):.1f}"  # type: ignore[arg-type]


DIAGNOSTIC_TITLES = {
    "Move_ratio": "predicted/GT UAV moves",
    "S_loc_prec": "precision-aware S_loc",
}
"""What the diagnostic columns (:data:`~vlm_bench.report.summary.DIAGNOSTICS`) are, in notes."""


def fmt_diagnostic(metric: str, value: object) -> str:
    """A diagnostic value: the move ratio with two decimals, S_loc with one."""
    if metric == "Move_ratio" and fmt(value) != "–":
        return f"{float(value):.2f}"  # type: ignore[arg-type]
    return fmt(value)


PARTIAL = "†"
"""Mark of a partial Overall (a row missing groups of the table), never bold."""


def partial_warnings(long: pd.DataFrame, by: By, grouping: Grouping) -> list[str]:
    """One warning per system whose Overall is partial, naming the groups it lacks (and the
    instruction rows, when not all of the system's rows lack the same)."""
    keys = by_columns(by)
    rows: dict[tuple[object, ...], list[str]] = {}
    for key in long[[*keys, "instruction"]].drop_duplicates().itertuples(index=False, name=None):
        rows.setdefault(tuple(key[:-1]), []).append(str(key[-1]))
    found: dict[tuple[tuple[object, ...], tuple[str, ...]], list[str]] = {}
    for key, groups in partial_overalls(long, by).items():
        found.setdefault((tuple(key[:-1]), tuple(groups)), []).append(str(key[-1]))
    out = []
    for (system, missing), instructions in found.items():
        name = " ".join(map(str, system))
        if instructions != rows[system]:
            name += f" ({', '.join(instructions)})"
        lacks = ", ".join(grouping.short.get(g, g) for g in missing)
        out.append(
            f"Partial Overall{PARTIAL}: {name} has no episode in {lacks}; its Overall averages "
            "the other groups only and is not comparable with complete rows."
        )
    return out


Coverage = dict[tuple[object, ...], tuple[int, int]]


def cell_text(value: object, metric: str, cell: tuple[object, ...], coverage: Coverage) -> str:
    """A table number; an execution value over only some of the cell's episodes gets the
    executed count beside it ("100.0 (20/60)", :func:`~vlm_bench.report.summary.exec_coverage`)."""
    text = fmt_diagnostic(metric, value)
    if metric in TABLE_EXEC_VALUES and text != "–" and cell in coverage:
        done, n = coverage[cell]
        text += f" ({done}/{n})"
    return text


def row_texts(
    wide: pd.DataFrame,
    key: tuple[object, ...],
    partial: dict[tuple[object, ...], list[str]],
    coverage: Coverage,
) -> list[str]:
    """A wide row's cells as text: a partial Overall marked, partial execution counted."""
    mark = PARTIAL if tuple(key) in partial else ""
    return [
        cell_text(v, m, (*key, g), coverage) + (mark if g == OVERALL and fmt(v) != "–" else "")
        for (g, m), v in zip(wide.columns, wide.loc[key].tolist(), strict=True)
    ]
