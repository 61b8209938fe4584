"""What went wrong, per system: parse tiers, error codes, execution failure codes, and S_loc
above a ``blind`` run."""

from __future__ import annotations

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.groups import SUITES, Grouping
from vlm_bench.report.paired import paired_table
from vlm_bench.report.report_options import BOOT_SEED, N_BOOT
from vlm_bench.report.summary import By, by_columns, system_order, system_rows

TIERS = ("valid", "repaired", "invalid")
"""Parse tiers (:data:`vlm_bench.types.parse.ParseTier`), in order."""


def parse_tier_rates(frame: pd.DataFrame, by: By = "model") -> pd.DataFrame:
    """Share of answered episodes per parse tier, in percent, per system.

    Returns:
        ``by`` columns, ``valid``, ``repaired``, ``invalid`` (summing to 100), ``n`` (answered
        episodes) and ``n_error`` (backend failures, in no tier).
    """
    keys = by_columns(by)
    rows = []
    for system in system_order(frame, keys):
        mine = system_rows(frame, keys, system)
        ok = mine[mine["status"] == "ok"]
        counts = ok["tier"].value_counts()
        n = len(ok)
        rows.append(
            {
                **dict(zip(keys, system, strict=True)),
                **{t: 100.0 * counts.get(t, 0) / n if n else float("nan") for t in TIERS},
                "n": n,
                "n_error": len(mine) - n,
            }
        )
    return pd.DataFrame(rows, columns=[*keys, *TIERS, "n", "n_error"])


def error_code_frequencies(frame: pd.DataFrame, by: By = "model") -> pd.DataFrame:
    """How often each error tag (parse codes and planning error types) occurs, per system.

    Returns:
        One row per system × code seen: ``by`` columns, ``code``, ``count`` (episodes with the
        tag) and ``share`` (percent of the system's answered episodes); codes by falling count.
    """
    ok = frame[frame["status"] == "ok"]
    codes = ok.assign(code=ok["error_tags"]).explode("code").fillna({"code": ""})
    return _frequencies(frame, ok, codes, by)


def failure_code_frequencies(frame: pd.DataFrame, by: By = "model") -> pd.DataFrame:
    """How often each execution failure code occurs, per system (runs that execute plans).

    Returns:
        One row per system × code seen: ``by`` columns, ``code`` (a
        :class:`~vlm_bench.types.execution.FailureCode` value, or ``no_plan``), ``count`` and
        ``share`` (percent of the system's answered episodes that were to be executed); codes by
        falling count.
    """
    executed = frame[(frame["status"] == "ok") & frame["exec_success"].notna()]
    codes = executed.assign(code=executed["exec_failure_code"].fillna(""))
    return _frequencies(frame, executed, codes, by)


def _frequencies(
    frame: pd.DataFrame, base: pd.DataFrame, codes: pd.DataFrame, by: By
) -> pd.DataFrame:
    """Counts of ``codes`` (one row per episode × code) per system, with shares of ``base``."""
    keys = by_columns(by)
    codes = codes[codes["code"] != ""]
    counts = codes.groupby([*keys, "code"], sort=False, dropna=False).size().rename("count")
    totals = base.groupby(keys, sort=False, dropna=False).size().rename("answered")
    out = counts.reset_index().merge(totals.reset_index(), on=keys)
    out["share"] = 100.0 * out["count"] / out["answered"]
    systems = system_order(frame, keys)
    out["_s"] = [systems.index(s) for s in out[keys].itertuples(index=False, name=None)]
    out = out.sort_values(["_s", "count", "code"], ascending=[True, False, True], kind="stable")
    return out[[*keys, "code", "count", "share"]].reset_index(drop=True)


def error_code_table(frame: pd.DataFrame, by: By = "model") -> pd.DataFrame:
    """:func:`error_code_frequencies` as systems × codes (share in percent, 0 when absent);
    codes by falling total count."""
    return _wide(frame, error_code_frequencies(frame, by), by)


def failure_code_table(frame: pd.DataFrame, by: By = "model") -> pd.DataFrame:
    """:func:`failure_code_frequencies` as systems × codes (share in percent, 0 when absent);
    codes by falling total count."""
    return _wide(frame, failure_code_frequencies(frame, by), by)


def _wide(frame: pd.DataFrame, long: pd.DataFrame, by: By) -> pd.DataFrame:
    keys = by_columns(by)
    if long.empty:
        return pd.DataFrame(columns=keys)
    order = long.groupby("code")["count"].sum().sort_values(ascending=False, kind="stable")
    wide = long.pivot_table(index=keys, columns="code", values="share", sort=False)
    systems = pd.MultiIndex.from_tuples(system_order(frame, keys), names=keys)
    wide = wide.reindex(index=systems if len(keys) > 1 else systems.get_level_values(0))
    wide = wide.reindex(columns=list(order.index)).fillna(0.0)
    wide.columns.name = None
    return wide.reset_index()


def blind_runs(frame: pd.DataFrame, by: By = "run") -> list[tuple[object, ...]]:
    """The systems whose model is the ``blind`` planner (a floor for S_loc)."""
    keys = by_columns(by)
    blind = frame[frame["model"] == "blind"]
    return system_order(blind, keys) if not blind.empty else []


def loc_over_blind_run(
    frame: pd.DataFrame,
    by: By = "run",
    grouping: Grouping = SUITES,
    n_boot: int = N_BOOT,
    seed: int = BOOT_SEED,
) -> pd.DataFrame:
    """S_loc of every system minus a ``blind`` run's S_loc on their common episodes.

    The first blind system is the reference (:func:`~vlm_bench.report.paired.paired_table` on
    ``S_loc``); empty when no blind run is in the frame. The per-episode ``Loc_over_blind``
    column needs no blind run: it recomputes the blind floor for each episode.
    """
    blind = blind_runs(frame, by)
    if not blind:
        return pd.DataFrame()
    reference = blind[0] if len(blind[0]) > 1 else blind[0][0]
    return paired_table(frame, reference, ("S_loc",), by, grouping, n_boot, seed)
