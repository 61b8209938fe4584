"""The paper table as LaTeX (booktabs), laid out like AIR-VLA's ``tab:vlm_planning_comprehensive``.

Rows are system × instruction (Exp./Imp.), labelled by display name (the model card's, or
``--label``); each column group has Plan, Loc, Obj, Skill, Tot, Succ (and Exec, Task when some
row was executed); the Overall group spans a system's two instruction rows with the ``both``
values, as the paper's "Overall Average" does. The best value of each column is bold (none where
every row ties; never a partial Overall or a partly executed value). Standard column spacing in
``\\footnotesize``, at natural size unless ``fit_width`` asks for ``\\resizebox``. The fragment
needs only ``booktabs`` (and ``graphicx`` with ``fit_width``): cells spanning two rows are lowered
with ``\\raisebox`` instead of ``multirow``, which minimal TeX installations lack.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.dataframe import loop_columns
from vlm_bench.report.groups import OVERALL, SUITES, Grouping
from vlm_bench.report.latex_cells import PARTIAL_MARK, best_value, cell, escape, natural_width
from vlm_bench.report.marks import DIAGNOSTIC_TITLES, fmt_diagnostic
from vlm_bench.report.summary import (
    BOTH,
    DIAGNOSTICS,
    TABLE_EXEC_VALUES,
    By,
    by_columns,
    exec_coverage,
    headline,
    partial_overalls,
    summary_wide,
    table_values,
)
from vlm_bench.report.tables import header, system_headers

INSTRUCTION_SHORT = {"explicit": "Exp.", "implicit": "Imp.", BOTH: "Both"}
_LOWER = r"\raisebox{-0.6\normalbaselineskip}[0pt][0pt]{%s}"
_HEAD = r"\raisebox{-1.2\normalbaselineskip}[0pt][0pt]{\textbf{%s}}"
_SIZE = r"\footnotesize"
"""Type size of the tables: the paper layout's 24 columns fit a landscape page at standard
column spacing (``--fit-width`` scales to the text width instead)."""


def latex_metrics(long: pd.DataFrame) -> list[str]:
    """The paper layout's metrics: the paper's columns (ΔLoc and the diagnostics are ours:
    they stay in the other formats and the table notes); Exec and Task, and the closed loop's
    Succ@k and Rec, only when some row was executed."""
    executed = "exec_success" in long.columns and long["exec_success"].notna().any()
    return [
        m
        for m in table_values(long)
        if m != "Loc_over_blind"
        and m not in DIAGNOSTICS
        and (executed or m not in TABLE_EXEC_VALUES)
    ]


def table_notes(
    long: pd.DataFrame,
    by: By,
    grouping: Grouping,
    names: Mapping[tuple[object, ...], str] | None = None,
) -> list[str]:
    """The notes under a table, once each: partial Overalls (one sentence naming every such
    row) and the diagnostics (each system's Overall move ratio and precision-aware S_loc)."""
    keys, names = by_columns(by), names or {}
    notes = []
    partial = partial_overalls(long, keys)
    if partial:
        lacking: dict[tuple[object, ...], set[str]] = {}
        for key, groups in partial.items():
            lacking.setdefault(tuple(key[:-1]), set()).update(groups)
        listed = "; ".join(
            f"{escape(names.get(s, '/'.join(map(str, s))))}: no "
            + ", ".join(escape(grouping.short.get(g, g)) for g in grouping.order if g in gs)
            for s, gs in lacking.items()
        )
        notes.append(
            PARTIAL_MARK + rf"Partial Overall, the mean of the groups the row has ({listed}); "
            "not comparable with complete rows."
        )
    shown = [d for d in DIAGNOSTICS if d in long.columns and long[d].notna().any()]
    if shown:
        overall = headline(long[long[grouping.column] == OVERALL], keys)
        parts = []
        for row in overall.to_dict("records"):
            system = tuple(row[k] for k in keys)
            values = " / ".join(fmt_diagnostic(d, row[d]) for d in shown)
            parts.append(f"{escape(names.get(system, '/'.join(map(str, system))))} {values}")
        what = " / ".join(escape(DIAGNOSTIC_TITLES[d]) for d in shown)
        notes.append(
            f"Diagnostics (Overall; not the paper's metrics), {what}: " + "; ".join(parts) + "."
        )
    return notes


def _blocks(wide: pd.DataFrame, n_keys: int) -> list[tuple[tuple[object, ...], list[str]]]:
    """Systems with their instruction rows (``both`` left out when explicit/implicit exist)."""
    blocks: dict[tuple[object, ...], list[str]] = {}
    for key in wide.index:
        blocks.setdefault(tuple(key[:n_keys]), []).append(str(key[n_keys]))
    out = []
    for system, rows in blocks.items():
        shown = [r for r in rows if r != BOTH] or rows
        out.append((system, shown))
    return out


def _overall_of(
    wide: pd.DataFrame, system: tuple[object, ...], rows: list[str]
) -> tuple[object, ...]:
    """The row whose overall values the block shows: ``both`` when present, else its row."""
    if len(rows) > 1 and (*system, BOTH) in wide.index:
        return (*system, BOTH)
    return (*system, rows[0])


def summary_latex(
    long: pd.DataFrame,
    by: By = "model",
    grouping: Grouping = SUITES,
    caption: str | None = None,
    label: str = "tab:vlm_planning",
    names: Mapping[tuple[object, ...], str] | None = None,
    fit_width: bool = False,
    metrics: Sequence[str] | None = None,
    note: str = "",
) -> str:
    """A ``table*`` float in the paper layout (see the module docstring).

    Args:
        long: The long summary (:func:`~vlm_bench.report.summary.summary_long`).
        by: Its system column(s). grouping: Its column groups.
        caption: Caption (default: the paper's, adapted). label: ``\\label``.
        names: Display name per system (:func:`~vlm_bench.report.names.display_names`);
            default the ``by`` values joined by '/'.
        fit_width: Scale the tabular to the text width (default: natural size).
        metrics: The metrics of each group (default: :func:`latex_metrics`).
        note: Text appended to the caption (the runs' protocol).
    """
    keys = by_columns(by)
    names = names or {}
    wide = summary_wide(long, keys, grouping)
    metrics = list(metrics) if metrics else latex_metrics(long)
    groups = [g for g in dict.fromkeys(c[0] for c in wide.columns) if g != OVERALL]
    blocks = _blocks(wide, len(keys)) if not wide.empty else []
    group_rows = [(*s, r) for s, rows in blocks for r in rows]
    overall_rows = [_overall_of(wide, s, rows) for s, rows in blocks]
    partial = partial_overalls(long, keys)
    coverage = exec_coverage(long, keys, grouping)

    def count(row: tuple[object, ...], group: str, metric: str) -> str:
        done = coverage.get((*row, group)) if metric in TABLE_EXEC_VALUES else None
        return f"{done[0]}/{done[1]}" if done else ""

    complete = [r for r in overall_rows if r not in partial]
    best = {
        (g, m): best_value([float(wide.loc[r, (g, m)]) for r in group_rows if not count(r, g, m)])
        for g in groups
        for m in metrics
    }
    best.update(
        {
            (OVERALL, m): best_value(
                [float(wide.loc[r, (OVERALL, m)]) for r in complete if not count(r, OVERALL, m)]
            )
            for m in metrics
        }
    )
    width = len(metrics)
    lead = 2
    spec = "ll" + "".join(" " + "r" * width for _ in [*groups, OVERALL])
    titles = [*(grouping.titles[g] for g in groups), "Overall Average"]
    head = [_HEAD % escape(h) for h in ["/".join(system_headers(keys)), "Instr."]]
    head += [rf"\multicolumn{{{width}}}{{c}}{{\textbf{{{escape(t)}}}}}" for t in titles]
    rules = " ".join(
        rf"\cmidrule(lr){{{lead + 1 + i * width}-{lead + (i + 1) * width}}}"
        for i in range(len(titles))
    )
    columns = [r"\textbf{Tot}" if m == "S_total" else header(m) for m in metrics]
    sub = ["/".join(system_headers(keys)), "Instr.", *(columns * len(titles))]
    body: list[list[str]] = []
    lines = [
        r"\begin{table*}[t]",
        r"\centering",
        rf"\caption{{{caption_with(caption or _default_caption(long, grouping), note)}}}",
        rf"\label{{{label}}}",
        _SIZE,
        *([r"\resizebox{\textwidth}{!}{%"] if fit_width else []),
        rf"\begin{{tabular}}{{{spec}}}",
        r"\toprule",
        " & ".join(head) + r" \\",
        rules,
        " & ".join([""] * lead + sub[lead:]) + r" \\",
        r"\midrule",
    ]
    for b, (system, rows) in enumerate(blocks):
        span = len(rows) == 2
        for i, row in enumerate(rows):
            first = i == 0
            name = escape(names.get(system, "/".join(map(str, system))))
            label_cell = (_LOWER % name if span else name) if first else ""
            cells = [label_cell, INSTRUCTION_SHORT.get(row, escape(row))]
            key = (*system, row)
            cells += [
                cell(float(wide.loc[key, (g, m)]), best[(g, m)], count=count(key, g, m))
                for g in groups
                for m in metrics
            ]
            if first or not span:
                source = overall_rows[b] if span else key
                overall = [
                    cell(
                        float(wide.loc[source, (OVERALL, m)]),
                        best[(OVERALL, m)],
                        source in partial,
                        count(source, OVERALL, m),
                    )
                    for m in metrics
                ]
                cells += [_LOWER % c if span else c for c in overall]
            else:
                cells += [""] * width
            lines.append(" & ".join(cells) + r" \\")
            body.append(cells)
        if b < len(blocks) - 1:
            lines.append(r"\midrule")
    lines += [r"\bottomrule", r"\end{tabular}" + ("}" if fit_width else "")]
    if not fit_width:
        lines.insert(0, f"% natural width about {natural_width([*body, sub]):.0f}pt")
    notes = table_notes(long, keys, grouping, names)
    if notes:
        lines.append(r"\par\smallskip\parbox{\linewidth}{\scriptsize " + " ".join(notes) + "}")
    lines.append(r"\end{table*}")
    return "\n".join(lines) + "\n"


def caption_with(caption: str, note: str) -> str:
    """``caption`` with ``note`` (plain text, escaped here) appended."""
    if not note.strip():
        return caption
    return f"{caption} {escape(note)}"


def _default_caption(long: pd.DataFrame, grouping: Grouping) -> str:
    executed = "exec_success" in long.columns
    text = (
        r"\textbf{VLM task planning.} Normalised sub-metric scores and planning success rate "
        r"(Succ, \%) per model, task group and instruction type (Exp.: explicit; Imp.: "
        r"implicit). Overall Average: unweighted mean of the "
        + ("suites" if grouping.name == "suites" else "columns")
        + r" over both instruction types. Best value per column in bold."
    )
    if executed:
        text += r" Exec: execution success (\%); Task: sub-goals completed (S\textsubscript{task})."
    if loop_columns(long.columns):
        text += (
            r" Closed loop: Succ@$k$, task success within $k$ replans (\%); Rec: share of the "
            r"round-0 failures recovered later (\%)."
        )
    return text


def latex_document(fragment: str) -> str:
    """A standalone landscape document around table fragments (compiles with ``pdflatex``).

    The page is A4 landscape, made wider where a table's natural width (the ``% natural width``
    comment :func:`summary_latex` writes) needs it, so every table fits its page unscaled.
    """
    widths = [float(w) for w in _WIDTH.findall(fragment)]
    page = max([_A4_LANDSCAPE_PT, *(1.1 * w + 2 * _MARGIN_PT for w in widths)])
    return "\n".join(
        [
            r"\documentclass{article}",
            rf"\usepackage[paperwidth={page:.0f}pt,paperheight=595pt,margin={_MARGIN_PT:.0f}pt]"
            r"{geometry}",
            r"\usepackage{booktabs}",
            r"\usepackage{graphicx}",
            r"\pagestyle{empty}",
            r"\begin{document}",
            fragment.rstrip("\n"),
            r"\end{document}",
            "",
        ]
    )


_A4_LANDSCAPE_PT = 842.0
_MARGIN_PT = 28.0
_WIDTH = re.compile(r"^% natural width about (\d+)pt$", re.M)
