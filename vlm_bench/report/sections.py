"""The statistics of a report as display tables: intervals, parse tiers, error codes, pairs."""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.groups import OVERALL, Grouping
from vlm_bench.report.marks import PARTIAL
from vlm_bench.report.summary import (
    EXEC_VALUES,
    By,
    by_columns,
    headline,
    system_order,
    system_rows,
)
from vlm_bench.report.tables import header, system_headers
from vlm_bench.report.text import p_value, with_ci


@dataclass(frozen=True)
class Section:
    """One display table: title, caption and formatted cells."""

    title: str
    caption: str
    frame: pd.DataFrame
    numeric: tuple[str, ...] = ()
    narrow: pd.DataFrame | None = None
    """The same content in fewer columns, for terminals the wide form does not fit."""


def _label(keys: list[str], row: dict[str, object]) -> dict[str, str]:
    return {h: str(row[k]) for h, k in zip(system_headers(keys), keys, strict=True)}


def ci_section(
    cis: pd.DataFrame,
    by: By,
    grouping: Grouping,
    n_boot: int,
    seed: int,
    level: float,
    partial: Collection[tuple[object, ...]] = (),
) -> Section:
    """Overall values with their intervals, one row per system (``both``, or its instruction);
    ``partial`` rows (``by`` values + instruction, missing a group) are marked."""
    keys = by_columns(by)
    overall = headline(cis[cis[grouping.column] == OVERALL], keys)
    metrics = list(dict.fromkeys(overall["metric"]))
    rows, narrow = [], []
    for system in system_order(overall, keys):
        cells = system_rows(overall, keys, system).set_index("metric")
        first = cells.iloc[0]
        label = {
            **_label(keys, dict(zip(keys, system, strict=True))),
            "Instr.": first["instruction"],
        }
        row: dict[str, object] = dict(label)
        mark = PARTIAL if (*system, first["instruction"]) in partial else ""
        for m in metrics:
            c = cells.loc[m] if m in cells.index else None
            row[header(m)] = "–" if c is None else with_ci(c["value"], c["lo"], c["hi"]) + mark
            if c is not None and m in EXEC_VALUES and int(c["n"]) < int(first["n"]):
                row[header(m)] = f"{row[header(m)]} ({int(c['n'])}/{int(first['n'])})"
            if c is not None:
                narrow.append({**label, "metric": header(m), "value [CI]": row[header(m)]})
        row["n"], row["tasks"] = int(first["n"]), int(first["n_tasks"])
        rows.append(row)
    frame = pd.DataFrame(rows)
    caption = (
        f"{round(level * 100)} % bootstrap intervals over tasks (resampled within each "
        f"{'suite' if grouping.name == 'suites' else 'paper column'}, {n_boot} replicates, "
        f"seed {seed}); Overall = mean of the groups; no interval where a group has one task."
    )
    if partial:
        caption += f" {PARTIAL} partial: the row lacks groups of the table (see the warning above)."
    numeric = tuple(c for c in frame.columns if c not in ("Instr.", *system_headers(keys)))
    return Section(
        "Overall with confidence intervals",
        caption,
        frame,
        numeric,
        narrow=pd.DataFrame(narrow),
    )


def tier_section(tiers: pd.DataFrame, by: By) -> Section:
    """Parse-tier rates per system."""
    keys = by_columns(by)
    rows = [
        {
            **_label(keys, r),
            "valid %": f"{r['valid']:.1f}",
            "repaired %": f"{r['repaired']:.1f}",
            "invalid %": f"{r['invalid']:.1f}",
            "n": r["n"],
            "backend errors": r["n_error"],
        }
        for r in tiers.to_dict("records")
    ]
    frame = pd.DataFrame(rows)
    caption = (
        "Share of answered episodes whose output parsed as valid JSON, needed repair, "
        "or held no plan."
    )
    return Section(
        "Parse tiers", caption, frame, ("valid %", "repaired %", "invalid %", "n", "backend errors")
    )


def code_section(
    table: pd.DataFrame,
    by: By,
    title: str = "Error codes",
    caption: str = "Percent of answered episodes with each error tag (parse codes, planning "
    "errors).",
) -> Section:
    """Code shares, one row per code and one column per system (fits narrow screens)."""
    keys = by_columns(by)
    codes = [c for c in table.columns if c not in keys]
    names = ["/".join(str(r[k]) for k in keys) for r in table.to_dict("records")]
    rows = [
        {"code": code, **{n: f"{v:.1f}" for n, v in zip(names, table[code], strict=True)}}
        for code in codes
    ]
    frame = pd.DataFrame(rows, columns=["code", *names])
    return Section(title, caption, frame, tuple(names))


def pair_section(pairs: pd.DataFrame, title: str, caption: str) -> Section:
    """Paired comparisons (:func:`vlm_bench.report.paired.paired_table`) as a display table;
    metrics with no common episode (a run that executes nothing) are left out, and so is the
    B column when every row has the same B (the title names it)."""
    rows = [
        {
            "A": r["a"],
            "B": r["b"],
            "metric": header(r["metric"]),
            "A − B": f"{r['diff']:.1f}",
            "95 % CI": "–" if r["lo"] != r["lo"] else f"[{r['lo']:.1f}, {r['hi']:.1f}]",
            "n": r["n"],
            "tasks": r["n_tasks"],
            "tasks A>B/A<B/=": f"{r['n_better']}/{r['n_worse']}/{r['n_tied']}",
            "sign p (tasks)": f"{p_value(r['p_sign'])} ({r['n_tasks']})",
        }
        for r in pairs.to_dict("records")
        if r["n"] > 0
    ]
    frame = pd.DataFrame(rows)
    if not frame.empty and frame["B"].nunique() == 1:
        frame = frame.drop(columns="B")
    numeric = ("A − B", "95 % CI", "n", "tasks", "tasks A>B/A<B/=", "sign p (tasks)")
    return Section(title, caption, frame, numeric)
