"""The report's tables as text: Markdown, CSV, Parquet or LaTeX (the terminal's rich tables
are printed by the CLI)."""

from __future__ import annotations

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.contents import Report
from vlm_bench.report.groups import Grouping
from vlm_bench.report.latex import caption_with, latex_document, summary_latex, table_notes
from vlm_bench.report.latex_compact import (
    compact_caption,
    compact_latex,
    latex_columns,
    two_column_document,
)
from vlm_bench.report.names import display_names
from vlm_bench.report.protocol_notes import protocol_note, protocol_warnings, row_protocols
from vlm_bench.report.summary import table_values
from vlm_bench.report.tables import summary_markdown
from vlm_bench.report.text import frame_markdown


def long_with_cis(report: Report) -> pd.DataFrame:
    """Every grouping's long summary stacked (``grouping``, ``group`` columns), with
    ``<metric>_lo``/``_hi`` interval columns where intervals were computed and each row's
    ``protocol`` (its runs' protocols joined by ``+``)."""
    by = list(report.options.by)
    parts = []
    for g in report.groupings:
        long = report.tables[g.name].rename(columns={g.column: "group"})
        cis = report.cis.get(g.name)
        if cis is not None and not cis.empty:
            bounds = cis.rename(columns={g.column: "group"}).pivot_table(
                index=[*by, "instruction", "group"],
                columns="metric",
                values=["lo", "hi"],
                sort=False,
                dropna=False,
            )
            bounds.columns = [f"{m}_{side}" for side, m in bounds.columns]
            ordered = [f"{m}_{s}" for m in table_values(long) for s in ("lo", "hi")]
            bounds = bounds.reindex(columns=[c for c in ordered if c in bounds.columns])
            long = long.merge(bounds.reset_index(), on=[*by, "instruction", "group"], how="left")
        parts.append(long.assign(grouping=g.name))
    out = pd.concat(parts, ignore_index=True)
    out = out.merge(row_protocols(report.frame, by), on=by, how="left")
    return out[["grouping", *[c for c in out.columns if c != "grouping"]]]


def render_tables(report: Report) -> str | bytes:
    """The tables in ``options.format`` (not ``terminal``: the CLI prints rich tables)."""
    options, by = report.options, list(report.options.by)
    fmt = options.format
    if fmt == "csv":
        return str(long_with_cis(report).to_csv(index=False, float_format="%.4f"))
    if fmt == "parquet":
        return bytes(long_with_cis(report).to_parquet(index=False))
    if fmt == "latex":
        names = display_names(report.frame, by)
        floats = [_latex_float(report, g, names) for g in report.groupings]
        text = "\n".join(floats)
        if not options.standalone:
            return text
        return latex_document(text) if options.layout == "paper" else two_column_document(text)
    parts = ["# vlm-bench report\n", protocol_note(report.frame) + "\n"]
    parts.extend(f"**Warning.** {w}\n" for w in protocol_warnings(report.frame, by))
    for g in report.groupings:
        title = "Our four suites" if g.name == "suites" else "The paper's three columns"
        parts.append(f"## {title}\n\n" + summary_markdown(report.tables[g.name], by, g))
    for section in report.sections:
        parts.append(f"## {section.title}\n\n" + frame_markdown(section.frame, section.numeric))
        parts.append(f"{section.caption}\n")
    return "\n".join(parts)


def _latex_float(report: Report, g: Grouping, names: dict[tuple[object, ...], str]) -> str:
    options, by, long = report.options, list(report.options.by), report.tables[g.name]
    metrics = latex_columns(long, options.layout, options.columns)
    if options.layout == "paper":
        return summary_latex(
            long,
            by,
            g,
            label=f"tab:vlm_planning_{g.name}",
            names=names,
            fit_width=options.fit_width,
            metrics=metrics,
            note=" ".join([protocol_note(report.frame), *protocol_warnings(report.frame, by)]),
        )
    return compact_latex(
        long,
        by,
        g,
        metrics,
        options.layout,
        caption=caption_with(
            compact_caption(long, g, metrics, options.layout),
            " ".join([protocol_note(report.frame), *protocol_warnings(report.frame, by)]),
        ),
        label=f"tab:vlm_planning_{g.name}_{options.layout}",
        names=names,
        notes=table_notes(long, by, g, names),
    )
