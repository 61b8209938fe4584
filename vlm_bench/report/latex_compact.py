"""Paste-ready LaTeX tables for a two-column paper, at natural size (never scaled).

Two layouts beside the paper's full one (:mod:`vlm_bench.report.latex`):

* ``column`` — a ``table`` float for ``\\columnwidth``: one row per system (its headline
  instruction: ``both`` where it has both), and for each chosen metric its Overall and one
  column per group. With the default metric (Tot) and the four suites it is six columns, about
  200 pt in ``\\footnotesize`` (8 pt in a 10 pt article), under a two-column article's
  ``\\columnwidth`` of about 240 pt.
* ``wide`` — a ``table*`` float for ``\\textwidth`` in ``\\scriptsize`` (7 pt in a 10 pt
  article): rows system × instruction as in the paper, each group (and Overall) with the chosen
  metrics (default Tot, Succ, and Exec when plans were executed).

``--columns`` picks the metrics of either layout (and of the paper layout). The notes (partial
Overalls, diagnostics) come once, under the tabular, in the table's own type size. Both are
``tabularx`` environments as wide as the column (the page): the name column takes the width
the numbers leave and wraps a long model name. The fragment needs ``booktabs`` and
``tabularx``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import UnknownNameError
from vlm_bench.report.dataframe import RECOVERED, loop_columns
from vlm_bench.report.groups import OVERALL, Grouping
from vlm_bench.report.latex_cells import best_value, cell, escape, natural_width
from vlm_bench.report.summary import (
    BOTH,
    By,
    by_columns,
    headline,
    partial_overalls,
    summary_wide,
    table_values,
)
from vlm_bench.report.tables import header, system_headers

INSTRUCTION_SHORT = {"explicit": "Exp.", "implicit": "Imp.", BOTH: "Both"}
_SIZES = {"column": r"\footnotesize", "wide": r"\scriptsize"}
_SEP = r"\setlength{\tabcolsep}{%s}"
_SEPS = {"column": "4pt", "wide": "3pt"}
_WIDTHS = {"column": r"\columnwidth", "wide": r"\textwidth"}
_NAME = r">{\raggedright\arraybackslash}X"
"""The name column: the width the numbers leave, a long name wrapped."""


def _head(metric: str) -> str:
    text = escape(header(metric))
    return rf"\textbf{{{text}}}" if metric == "S_total" else text


def _rows(long: pd.DataFrame, keys: list[str], layout: str) -> list[tuple[object, ...]]:
    """Row keys (system values + instruction): the headline instruction per system in the
    column layout, every instruction but ``both`` (where the system has two) in the wide one."""
    rows = list(dict.fromkeys(long[[*keys, "instruction"]].itertuples(index=False, name=None)))
    if layout == "column":
        shown = set(headline(long, keys)[[*keys, "instruction"]].itertuples(index=False, name=None))
        return [r for r in rows if r in shown]
    systems: dict[tuple[object, ...], list[tuple[object, ...]]] = {}
    for r in rows:
        systems.setdefault(tuple(r[:-1]), []).append(r)
    return [r for rs in systems.values() for r in ([x for x in rs if x[-1] != BOTH] or rs)]


def compact_latex(
    long: pd.DataFrame,
    by: By,
    grouping: Grouping,
    metrics: Sequence[str],
    layout: str,
    *,
    caption: str,
    label: str,
    names: Mapping[tuple[object, ...], str] | None = None,
    notes: Sequence[str] = (),
) -> str:
    """The ``column`` or ``wide`` float (see the module docstring).

    Args:
        long: The long summary. by: Its system column(s). grouping: Its column groups.
        metrics: Value columns shown, in order.
        layout: ``column`` or ``wide``.
        caption: The caption (LaTeX). label: The ``\\label``.
        names: Display name per system (default: the values joined by '/').
        notes: Table notes (LaTeX), printed once under the tabular.
    """
    keys = by_columns(by)
    names = names or {}
    wide = summary_wide(long, keys, grouping)
    groups = [g for g in dict.fromkeys(c[0] for c in wide.columns) if g != OVERALL]
    order = [OVERALL, *groups] if layout == "column" else [*groups, OVERALL]
    rows = _rows(long, keys, layout) if not wide.empty else []
    partial = partial_overalls(long, keys)
    best = {
        (g, m): best_value(
            [
                float(wide.loc[r, (g, m)])
                for r in rows
                if not (g == OVERALL and r in partial) and (g, m) in wide.columns
            ]
        )
        for g in order
        for m in metrics
    }
    lead = 1 + (layout == "wide")
    width = len(order)
    title = "/".join(system_headers(keys))
    if layout == "column":
        # metric on top, groups below: each metric is one block of Overall + groups
        spec = _NAME + "".join(" " + "r" * width for _ in metrics)
        top = [""] * lead + [rf"\multicolumn{{{width}}}{{c}}{{{_head(m)}}}" for m in metrics]
        sub = [escape(title)] + [
            escape(grouping.short.get(g, g) if g != OVERALL else "Overall")
            for _ in metrics
            for g in order
        ]
        cells_of = [(g, m) for m in metrics for g in order]
    else:
        width = len(metrics)
        spec = _NAME + "l" + "".join(" " + "r" * width for _ in order)
        top = [""] * lead + [
            rf"\multicolumn{{{width}}}{{c}}{{{escape(grouping.short.get(g, 'Overall'))}}}"
            for g in order
        ]
        sub = [escape(title), "Instr."] + [_head(m) for _ in order for m in metrics]
        cells_of = [(g, m) for g in order for m in metrics]
    blocks = len(top) - lead
    rules = " ".join(
        rf"\cmidrule(lr){{{lead + 1 + i * width}-{lead + (i + 1) * width}}}" for i in range(blocks)
    )
    body: list[list[str]] = []
    previous = None
    for row in rows:
        system = tuple(row[:-1])
        name = escape(names.get(system, "/".join(map(str, system))))
        if layout == "wide" and system == previous:
            name = ""  # a system's second instruction row
        previous = system
        instruction = INSTRUCTION_SHORT.get(str(row[-1]), escape(str(row[-1])))
        label_cells = [name] if layout == "column" else [name, instruction]
        values = []
        for g, m in cells_of:
            value = float(wide.loc[row, (g, m)]) if (g, m) in wide.columns else math.nan
            values.append(cell(value, best[(g, m)], partial=g == OVERALL and row in partial))
        body.append([*label_cells, *values])
    numbers = natural_width([c[lead:] for c in [*body, sub]], _SEPS[layout])
    size = _SIZES[layout]
    float_env = "table" if layout == "column" else "table*"
    lines = [
        rf"% needs booktabs, tabularx; numbers about {numbers:.0f}pt wide",
        rf"\begin{{{float_env}}}[t]",
        r"\centering",
        rf"\caption{{{caption}}}",
        rf"\label{{{label}}}",
        size,
        _SEP % _SEPS[layout],
        rf"\begin{{tabularx}}{{{_WIDTHS[layout]}}}{{{spec}}}",
        r"\toprule",
        " & ".join(top) + r" \\",
        rules,
        " & ".join(sub) + r" \\",
        r"\midrule",
        *(" & ".join(cells) + r" \\" for cells in body),
        r"\bottomrule",
        r"\end{tabularx}",
    ]
    if notes:
        lines.append(r"\par\smallskip\parbox{\linewidth}{" + size + " " + " ".join(notes) + "}")
    lines.append(rf"\end{{{float_env}}}")
    return "\n".join(lines) + "\n"


def latex_columns(long: pd.DataFrame, layout: str, requested: Sequence[str] = ()) -> list[str]:
    """The metrics of a LaTeX table: ``requested`` (value columns or their headers: ``Tot``,
    ``S_total``, ``Succ``, ``Exec``, ``Succ@3``), else the layout's default (see the module
    docstring; the paper layout: :func:`~vlm_bench.report.latex.latex_metrics`).

    Raises:
        UnknownNameError: A requested metric the table does not have (lists those it has).
    """
    from vlm_bench.report.latex import latex_metrics

    available = [m for m in table_values(long) if m in long.columns]
    if requested:
        by_name = {**{header(m).lower(): m for m in available}, **{m.lower(): m for m in available}}
        out = []
        for name in requested:
            if name.lower() not in by_name:
                raise UnknownNameError("--columns metric", name, [header(m) for m in available])
            out.append(by_name[name.lower()])
        return list(dict.fromkeys(out))
    if layout == "paper":
        return latex_metrics(long)
    if layout == "column":
        return ["S_total"]
    executed = "exec_success" in long.columns and long["exec_success"].notna().any()
    loops = [m for m in loop_columns(long.columns) if m != RECOVERED]
    return ["S_total", "Succ", *(["exec_success"] if executed else []), *loops[-1:]]


def compact_caption(
    long: pd.DataFrame, grouping: Grouping, metrics: Sequence[str], layout: str
) -> str:
    """The caption of a compact table: what its rows and columns are."""
    names = ", ".join(escape(header(m)) for m in metrics)
    one, many = ("suite", "suites") if grouping.name == "suites" else ("column", "paper's columns")
    rows = (
        "one row per model, explicit and implicit instructions averaged"
        if layout == "column"
        else "a row per model and instruction (Exp.: explicit; Imp.: implicit)"
    )
    text = (
        rf"\textbf{{VLM task planning.}} {names} per {one} and Overall (the unweighted mean of "
        rf"the {many}); {rows}. Best value per column in bold."
    )
    legend = {
        "S_total": r"Tot: total planning score",
        "Succ": r"Succ: exact plans (\%)",
        "exec_success": r"Exec: execution success (\%)",
        "S_task": r"Task: sub-goals completed",
        RECOVERED: r"Rec: round-0 failures recovered (\%)",
    }
    said = [legend[m] for m in metrics if m in legend]
    if loop_columns(metrics):
        said.append(r"Succ@$k$: task success within $k$ replans (\%)")
    return text + (" " + "; ".join(said) + "." if said else "")


def two_column_document(fragment: str) -> str:
    """A standalone two-column article (10 pt) around compact table fragments: the page the
    ``column`` and ``wide`` layouts are made for (compiles with ``pdflatex``)."""
    return "\n".join(
        [
            r"\documentclass[twocolumn]{article}",
            r"\usepackage{booktabs}",
            r"\usepackage{tabularx}",
            r"\pagestyle{empty}",
            r"\begin{document}",
            fragment.rstrip("\n"),
            r"\end{document}",
            "",
        ]
    )
