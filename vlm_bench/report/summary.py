"""The paper's planning table (AIR-VLA Table "VLM task planning"): long and wide forms.

Aggregation, documented once here:

* A **group cell** (system × instruction × group, where a group is a suite or one of the paper's
  columns, :mod:`vlm_bench.report.groups`) is the mean over that cell's episodes; ``Succ`` is the
  share of exact plans in percent.
* **Overall** (group ``overall``) is the *unweighted mean of the group cells* of the row, like the
  paper's "Overall Average" (which averages its columns; suites have 20/15/15/10 tasks, so this
  differs from a mean over episodes when the suites are all present).
* **Instruction ``both``** averages the explicit and implicit cells of each group with equal
  weight; its overall is again the mean of its group cells, i.e. the paper's per-model overall.
* Records whose backend failed (``status == "error"``) are left out of the means and counted in
  ``n_error``; a resume retries them. A group cell with no answered episode is NaN, and so are
  the overall and ``both`` values built from it (they would otherwise cover fewer groups).
* An overall is comparable only over the same groups: a row with no episode at all in some group
  of the table (a run of one suite beside runs of all four) keeps its mean over the groups it
  has, but ``missing_groups`` names the others; the tables mark that Overall *partial* (never
  bold, never best) and warn. A ``both`` cell needs every instruction of its system.
* Runs that execute plans add the execution columns (:data:`EXEC_VALUES`): ``exec_success`` is
  the share of answered episodes whose execution succeeded, in percent; ``S_task``, ``S_pos``,
  ``S_arm``, ``S_safe`` and ``VLA_total`` are means over the answered episodes, an output with no
  plan to execute counting 0 in each. They aggregate like the planning metrics. Runs that do not
  execute plans have none of these columns (NaN when compared with runs that do).
* Closed-loop runs add ``Succ@1``..``Succ@K`` (the task succeeded within k replans; Succ@0 is
  ``exec_success``) and ``Recovered`` (the share of round-0 failures that a later round
  recovered), in percent; open-loop runs have NaN there. ``Recovered`` has no value in a cell
  where round 0 never failed, so its Overall and ``both`` values average the cells that have
  one.
* ``n_executed`` (with the execution columns) counts a cell's answered episodes that have
  execution values. Where it is below ``n`` (a ``--by`` row pooling executing and planning-only
  runs) the execution values cover only those episodes, and the tables print the count beside
  them ("100.0 (20/60)"); where it is 0 they print "–".

A *system* (a table row, with the instruction) is one value of the ``by`` column(s): ``model`` by
default, ``run`` to compare ablations of one model, or several columns (``views, resolution``).
"""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.dataframe import EXEC_METRICS, METRICS, RECOVERED, loop_columns
from vlm_bench.report.groups import OVERALL, SUITES, Grouping

__all__ = ["OVERALL"]

BOTH = "both"
"""``instruction`` value of rows that average the two instruction variants."""
VALUES = (*METRICS, "Succ", "Loc_over_blind")
"""Value columns of the summary: the paper's, then S_loc above the ``blind`` floor on the same
episodes (:mod:`vlm_bench.report.floors`)."""
DIAGNOSTICS = ("Move_ratio", "S_loc_prec")
"""Diagnostic value columns, where the episode frame has them: the predicted plan's UAV moves
over the GT plan's (mean ratio) and the precision-aware S_loc (which also charges extra moves).
Not the paper's metrics: the paper's S_loc stays the headline; they follow ``Loc_over_blind``."""
EXEC_VALUES = EXEC_METRICS
"""Value columns added when the records include executing runs (see the module docstring)."""
TABLE_EXEC_VALUES = ("exec_success", "S_task")
"""Execution columns of the printed tables (the VLA metrics are in ``summary.csv`` only)."""
MISSING = "missing_groups"
"""Column of :func:`summary_long`: on overall rows, the table's groups the row has no episode
in, comma-separated ("" when it covers them all: a complete Overall); "" on other rows."""
SUMMARY_COLUMNS = (
    "model", "instruction", "suite", *VALUES, *DIAGNOSTICS, "n", "n_error", MISSING
)  # fmt: skip
"""Columns of :func:`summary_long` (and ``summary.csv``) without execution; with execution,
:data:`EXEC_VALUES` follow the diagnostics."""
PERCENT = ("Succ", "exec_success")
"""Boolean columns reported as percentages (with the closed loop's: :func:`is_percent`)."""


def is_percent(column: str) -> bool:
    """Whether ``column`` is a per-episode outcome the tables give in percent."""
    return column in PERCENT or column == RECOVERED or column.startswith("Succ@")


INSTRUCTION_ORDER = ["explicit", "implicit", BOTH]

By = str | Sequence[str]
"""One column or several naming a table row's system."""


def by_columns(by: By) -> list[str]:
    """``by`` as a list of column names."""
    return [by] if isinstance(by, str) else list(by)


def system_rows(frame: pd.DataFrame, by: By, system: tuple[object, ...]) -> pd.DataFrame:
    """The rows of one system (a tuple of ``by`` values)."""
    keys = by_columns(by)
    return frame[(frame[keys] == pd.Series(system, index=keys)).all(axis=1)]


def headline(rows: pd.DataFrame, by: By) -> pd.DataFrame:
    """The rows of each system's headline instruction: ``both`` where the system has both
    variants, else its only one (what the paper's per-model Overall reports)."""
    keys = by_columns(by)
    both = (rows["instruction"] == BOTH).groupby([rows[k] for k in keys], dropna=False)
    return rows[(rows["instruction"] == BOTH) | ~both.transform("any")]


def summary_values(frame: pd.DataFrame) -> tuple[str, ...]:
    """The value columns a summary of ``frame`` has: :data:`VALUES` (and the
    :data:`DIAGNOSTICS` the frame has), plus :data:`EXEC_VALUES` when an answered episode has
    execution values (its run executes plans), plus the closed loop's Succ@k and Recovered."""
    ok = frame[frame["status"] == "ok"]
    values = (*VALUES, *(d for d in DIAGNOSTICS if d in frame.columns))
    if "exec_success" in frame.columns and ok["exec_success"].notna().any():
        loops = loop_columns(frame.columns)
        closed = bool(loops) and ok[loops[0]].notna().any()
        return (*values, *EXEC_VALUES, *(loops if closed else ()))
    return values


def table_values(long: pd.DataFrame) -> tuple[str, ...]:
    """The value columns of the printed tables for a long summary (with the closed loop's
    Succ@k and Recovered where some run is closed-loop)."""
    values = (*VALUES, *(d for d in DIAGNOSTICS if d in long.columns))
    if "exec_success" not in long.columns:
        return values
    return (*values, *TABLE_EXEC_VALUES, *loop_columns(long.columns))


def _cells(frame: pd.DataFrame, keys: list[str], values: tuple[str, ...]) -> pd.DataFrame:
    ok = frame[frame["status"] == "ok"].copy()
    for col in values:
        if is_percent(col):
            ok[col] = ok[col].astype(float) * 100.0
    grouped = ok.groupby(keys, sort=False, dropna=False)
    cells = grouped[list(values)].mean()
    cells["n"] = grouped.size()
    counts = ["n", "n_error"]
    if "exec_success" in values:
        cells["n_executed"] = grouped["exec_success"].count()
        counts.append("n_executed")
    errors = frame[frame["status"] != "ok"].groupby(keys, sort=False, dropna=False).size()
    cells = cells.join(errors.rename("n_error"), how="outer")
    cells[counts] = cells[counts].fillna(0).astype(int)
    return cells.reset_index()


def _counts(values: tuple[str, ...]) -> list[str]:
    return ["n", "n_error", "n_executed"] if "exec_success" in values else ["n", "n_error"]


def _strict_mean(col: pd.Series) -> float:
    # A cell whose episodes all failed is NaN and makes the mean NaN: an overall must cover the
    # same groups to be comparable (resume to retry the failures).
    return float(col.mean(skipna=False))


def _means(values: tuple[str, ...]) -> dict[str, object]:
    """How each value's cells combine: strictly, except the recovery rate (a cell where round 0
    never failed has none)."""
    return {v: ("mean" if v == RECOVERED else _strict_mean) for v in values}


def _overall(
    cells: pd.DataFrame, by: list[str], group: str, values: tuple[str, ...], table: list[str]
) -> pd.DataFrame:
    grouped = cells.groupby([*by, "instruction"], sort=False, dropna=False)
    out = grouped[list(values)].agg(_means(values))
    out[_counts(values)] = grouped[_counts(values)].sum()
    covered = grouped[group].agg(set)
    out[MISSING] = [",".join(g for g in table if g not in have) for have in covered]
    out = out.reset_index()
    out[group] = OVERALL
    return out


def _both(cells: pd.DataFrame, by: list[str], group: str, values: tuple[str, ...]) -> pd.DataFrame:
    variants = cells.groupby(by, dropna=False)["instruction"].transform("nunique")
    present = cells.groupby([*by, group], dropna=False)["instruction"].transform("nunique")
    # A group some instruction never ran has no ``both`` cell (it would be one instruction's).
    grouped = cells[(variants > 1) & (present == variants)].groupby(
        [*by, group], sort=False, dropna=False
    )
    out = grouped[list(values)].agg(_means(values))
    out[_counts(values)] = grouped[_counts(values)].sum()
    out = out.reset_index()
    out["instruction"] = BOTH
    return out


def system_order(frame: pd.DataFrame, by: By) -> list[tuple[object, ...]]:
    """The systems (tuples of ``by`` values) in order of first appearance."""
    return list(dict.fromkeys(frame[by_columns(by)].itertuples(index=False, name=None)))


def summary_long(
    frame: pd.DataFrame, by: By = "model", grouping: Grouping = SUITES
) -> pd.DataFrame:
    """Group cells plus overall and ``both`` rows (see the module docstring).

    Args:
        frame: Episode rows (:func:`vlm_bench.report.load` or :func:`records_frame`).
        by: Column(s) that name a table row's system (``model``; ``run`` to compare ablations
            of one model; ``["views", "resolution"]``).
        grouping: Column groups: :data:`~vlm_bench.report.groups.SUITES` or the paper's
            (:func:`~vlm_bench.report.groups.paper_grouping`).

    Returns:
        Columns ``by``, ``instruction``, the grouping's column (``suite``), the values
        (:data:`VALUES`, with :data:`EXEC_VALUES` after ``Loc_over_blind`` when the records
        include executing runs), ``n``, ``n_error`` (``n_executed`` with execution) and
        ``missing_groups``; rows ordered by system (first
        appearance), instruction (explicit, implicit, both), group (table order, overall last).
    """
    keys, group = by_columns(by), grouping.column
    if frame.empty:
        return pd.DataFrame(columns=[*keys, "instruction", group, *VALUES, "n", "n_error", MISSING])
    frame = grouping.assign(frame)
    values = summary_values(frame)
    cells = _cells(frame, [*keys, "instruction", group], values)
    both = _both(cells, keys, group, values)
    rows = pd.concat([cells, both], ignore_index=True) if not both.empty else cells
    present = [g for g in grouping.order if g in set(frame[group])]
    overall = _overall(rows, keys, group, values, present)
    table = pd.concat([rows, overall], ignore_index=True)
    table[MISSING] = table[MISSING].fillna("")
    systems = system_order(frame, keys)
    table["_s"] = [systems.index(s) for s in table[keys].itertuples(index=False, name=None)]
    table["_i"] = table["instruction"].map(INSTRUCTION_ORDER.index)
    table["_g"] = table[group].map(grouping.position)
    table = table.sort_values(["_s", "_i", "_g"], kind="stable")
    columns = [*keys, "instruction", group, *values, *_counts(values), MISSING]
    return table[columns].reset_index(drop=True)


def exec_coverage(
    long: pd.DataFrame, by: By = "model", grouping: Grouping = SUITES
) -> dict[tuple[object, ...], tuple[int, int]]:
    """(``by`` values, instruction, group) → (executed, answered) episodes, for the cells whose
    execution values cover only some of their episodes (see the module docstring)."""
    if "n_executed" not in long.columns:
        return {}
    keys = by_columns(by)
    rows = long[(long["n_executed"] > 0) & (long["n_executed"] < long["n"])]
    return {
        (*(r[k] for k in keys), r["instruction"], r[grouping.column]): (
            int(r["n_executed"]),
            int(r["n"]),
        )
        for r in rows.to_dict("records")
    }


def partial_overalls(long: pd.DataFrame, by: By = "model") -> dict[tuple[object, ...], list[str]]:
    """Rows (``by`` values + instruction) whose Overall misses groups of the table, with the
    missing group values (see the module docstring)."""
    keys = by_columns(by)
    if MISSING not in long.columns:
        return {}
    rows = long[long[MISSING].fillna("") != ""]
    return {
        (*(r[k] for k in keys), r["instruction"]): str(r[MISSING]).split(",")
        for r in rows.to_dict("records")
    }


def summary_wide(long: pd.DataFrame, by: By = "model", grouping: Grouping = SUITES) -> pd.DataFrame:
    """The paper layout: rows system × instruction; columns (group, metric) then overall.

    Column labels are ``(group value or "overall", metric)`` tuples; only groups present appear.
    Metrics are :func:`table_values` (the paper's, then ``exec_success`` and ``S_task`` when
    plans were executed).
    """
    if long.empty:
        return pd.DataFrame()
    keys, group = by_columns(by), grouping.column
    values = list(table_values(long))
    rows = list(dict.fromkeys(long[[*keys, "instruction"]].itertuples(index=False, name=None)))
    present = set(long[group])
    groups = [g for g in [*grouping.order, OVERALL] if g in present]
    found: dict[tuple[object, ...], dict[str, float]] = {}
    for record in long[[*keys, "instruction", group, *values]].to_dict("records"):
        key = (*(record[k] for k in keys), record["instruction"], record[group])
        found[key] = record
    data = [
        [float(found.get((*row, g), {}).get(m, float("nan"))) for g in groups for m in values]
        for row in rows
    ]
    return pd.DataFrame(
        data,
        index=pd.MultiIndex.from_tuples(rows, names=[*keys, "instruction"]),
        columns=pd.MultiIndex.from_product([groups, values]),
    )


def sort_systems(
    long: pd.DataFrame,
    by: By = "model",
    grouping: Grouping = SUITES,
    metric: str = "S_total",
    ascending: bool = True,
) -> pd.DataFrame:
    """``long`` with its systems ordered by their overall ``metric`` (the paper sorts by overall
    Tot, ascending); a system's overall is its ``both`` row, or its first instruction's. Systems
    without a complete overall (a missing group) go last; ties keep their order."""
    keys = by_columns(by)
    overall = headline(long[long[grouping.column] == OVERALL], keys)
    if MISSING in overall.columns:
        overall = overall[overall[MISSING].fillna("") == ""]
    score = {tuple(r[k] for k in keys): float(r[metric]) for r in overall.to_dict("records")}
    systems = system_order(long, keys)
    sign = 1.0 if ascending else -1.0

    def rank(system: tuple[object, ...]) -> tuple[bool, float, int]:
        value = score.get(system, float("nan"))
        return (value != value, sign * value if value == value else 0.0, systems.index(system))

    ranked = sorted(systems, key=rank)
    position = [ranked.index(s) for s in long[keys].itertuples(index=False, name=None)]
    return long.assign(_r=position).sort_values("_r", kind="stable").drop(columns="_r")
