"""The paper's planning table (AIR-VLA Table "VLM task planning"): long and wide forms.

Aggregation, documented once here:

* A **suite cell** (model × instruction × suite) is the mean over that cell's episodes; ``Succ``
  is the share of exact plans in percent.
* **Overall** (``suite == "overall"``) is the *unweighted mean of the suite cells* of the row,
  like the paper's "Overall Average" (which averages its suite columns; suites have 20/15/15/10
  tasks, so this differs from a mean over episodes when the suites are all present).
* **Instruction ``both``** averages the explicit and implicit cells of each suite with equal
  weight; its overall is again the mean of its suite cells, i.e. the paper's per-model overall.
* Records whose backend failed (``status == "error"``) are left out of the means and counted in
  ``n_error``; a resume retries them. A suite cell with no answered episode is NaN, and so are
  the overall and ``both`` values built from it (they would otherwise cover fewer suites).
* Runs that execute plans add the execution columns (:data:`EXEC_VALUES`): ``exec_success`` is
  the share of answered episodes whose execution succeeded, in percent; ``S_task``, ``S_pos``,
  ``S_arm``, ``S_safe`` and ``VLA_total`` are means over the answered episodes, an output with no
  plan to execute counting 0 in each. They aggregate like the planning metrics. Runs that do not
  execute plans have none of these columns (NaN when compared with runs that do).
"""

from __future__ import annotations

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.frame import EXEC_METRICS, METRICS
from vlm_bench.types.task import Suite

OVERALL = "overall"
"""``suite`` value of overall rows."""
BOTH = "both"
"""``instruction`` value of rows that average the two instruction variants."""
VALUES = (*METRICS, "Succ", "Loc_over_blind")
"""Value columns of the summary: the paper's, then S_loc above the ``blind`` floor on the same
episodes (:mod:`vlm_bench.report.floors`)."""
EXEC_VALUES = EXEC_METRICS
"""Value columns added when the records include executing runs (see the module docstring)."""
TABLE_EXEC_VALUES = ("exec_success", "S_task")
"""Execution columns of the printed tables (the VLA metrics are in ``summary.csv`` only)."""
SUMMARY_COLUMNS = ("model", "instruction", "suite", *VALUES, "n", "n_error")
"""Columns of :func:`summary_long` (and ``summary.csv``) without execution; with execution,
:data:`EXEC_VALUES` follow ``Loc_over_blind``."""
PERCENT = ("Succ", "exec_success")
"""Boolean columns reported as percentages."""

SUITE_ORDER = [s.value for s in Suite]
INSTRUCTION_ORDER = ["explicit", "implicit", BOTH]


def summary_values(frame: pd.DataFrame) -> tuple[str, ...]:
    """The value columns a summary of ``frame`` has: :data:`VALUES`, plus :data:`EXEC_VALUES`
    when an answered episode has execution values (its run executes plans)."""
    ok = frame[frame["status"] == "ok"]
    if "exec_success" in frame.columns and ok["exec_success"].notna().any():
        return (*VALUES, *EXEC_VALUES)
    return VALUES


def table_values(long: pd.DataFrame) -> tuple[str, ...]:
    """The value columns of the printed tables for a long summary."""
    return (*VALUES, *TABLE_EXEC_VALUES) if "exec_success" in long.columns else VALUES


def _cells(frame: pd.DataFrame, by: str, values: tuple[str, ...]) -> pd.DataFrame:
    ok = frame[frame["status"] == "ok"].copy()
    for col in PERCENT:
        if col in values:
            ok[col] = ok[col].astype(float) * 100.0
    keys = [by, "instruction", "suite"]
    cells = ok.groupby(keys, sort=False)[list(values)].mean()
    cells["n"] = ok.groupby(keys, sort=False).size()
    errors = frame[frame["status"] != "ok"].groupby(keys, sort=False).size()
    cells = cells.join(errors.rename("n_error"), how="outer")
    cells[["n", "n_error"]] = cells[["n", "n_error"]].fillna(0).astype(int)
    return cells.reset_index()


def _overall(cells: pd.DataFrame, by: str, values: tuple[str, ...]) -> pd.DataFrame:
    grouped = cells.groupby([by, "instruction"], sort=False)
    # A cell whose episodes all failed is NaN and makes the overall NaN: an overall must cover
    # the same suites to be comparable (resume to retry the failures).
    out = grouped[list(values)].agg(lambda col: col.mean(skipna=False))
    out[["n", "n_error"]] = grouped[["n", "n_error"]].sum()
    out = out.reset_index()
    out["suite"] = OVERALL
    return out


def _both(cells: pd.DataFrame, by: str, values: tuple[str, ...]) -> pd.DataFrame:
    multi = cells.groupby(by)["instruction"].transform("nunique") > 1
    grouped = cells[multi].groupby([by, "suite"], sort=False)
    out = grouped[list(values)].agg(lambda col: col.mean(skipna=False))
    out[["n", "n_error"]] = grouped[["n", "n_error"]].sum()
    out = out.reset_index()
    out["instruction"] = BOTH
    return out


def summary_long(frame: pd.DataFrame, by: str = "model") -> pd.DataFrame:
    """Suite cells plus overall and ``both`` rows (see the module docstring).

    Args:
        frame: Episode rows from :func:`vlm_bench.report.frame.records_frame`.
        by: Column that names a table row's system (``model``, or ``run_id`` to compare
            ablations of one model).

    Returns:
        Columns :data:`SUMMARY_COLUMNS` (with ``by`` in place of ``model``; the execution
        columns :data:`EXEC_VALUES` after ``Loc_over_blind`` when the records include
        executing runs),
        rows ordered by system (first appearance), instruction (explicit, implicit, both), suite
        (paper order, overall last).
    """
    if frame.empty:
        return pd.DataFrame(columns=[by, *SUMMARY_COLUMNS[1:]])
    values = summary_values(frame)
    columns = [by, "instruction", "suite", *values, "n", "n_error"]
    cells = _cells(frame, by, values)
    both = _both(cells, by, values)
    suite_rows = pd.concat([cells, both], ignore_index=True) if not both.empty else cells
    table = pd.concat([suite_rows, _overall(suite_rows, by, values)], ignore_index=True)
    systems = list(dict.fromkeys(frame[by]))
    table["_s"] = table[by].map(systems.index)
    table["_i"] = table["instruction"].map(INSTRUCTION_ORDER.index)
    table["_u"] = table["suite"].map(
        lambda s: len(SUITE_ORDER) if s == OVERALL else SUITE_ORDER.index(s)
    )
    table = table.sort_values(["_s", "_i", "_u"], kind="stable")
    return table[columns].reset_index(drop=True)


def summary_wide(long: pd.DataFrame, by: str = "model") -> pd.DataFrame:
    """The paper layout: rows system × instruction; columns (suite, metric) then overall.

    Column labels are ``(suite value or "overall", metric)`` tuples; only suites present appear.
    Metrics are :func:`table_values` (the paper's, then ``exec_success`` and ``S_task`` when
    plans were executed).
    """
    if long.empty:
        return pd.DataFrame()
    values = list(table_values(long))
    wide = long.pivot_table(
        index=[by, "instruction"], columns="suite", values=values, sort=False, dropna=False
    )
    suites = [s for s in [*SUITE_ORDER, OVERALL] if s in set(long["suite"])]
    wide = wide.swaplevel(0, 1, axis=1)
    wide = wide.reindex(columns=pd.MultiIndex.from_product([suites, values]))
    rows = list(dict.fromkeys(zip(long[by], long["instruction"], strict=True)))
    return wide.reindex(pd.MultiIndex.from_tuples(rows, names=[by, "instruction"]))
