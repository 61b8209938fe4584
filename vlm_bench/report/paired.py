"""Paired comparison of two systems on their common episodes: difference, CI, sign test.

Two runs over the same episodes differ less than their marginal intervals suggest (an episode
that is hard for one model tends to be hard for the other); pairing removes that shared part.
Common episodes are those both systems answered (same task, seed and instruction). The
difference is the table's overall estimator applied to the per-episode differences (group cells,
then the mean of the groups), so with every episode common it equals the difference of the two
table values; its interval is the task-clustered bootstrap of :mod:`vlm_bench.report.bootstrap`.
The sign test is at the task level: episodes of one task are not independent (its explicit and
implicit episodes share the scene, and a planner that ignores the instruction answers both
alike), so each task is one unit, its sign that of its mean difference over the common
episodes. It counts tasks where A is better / worse (ties dropped) and gives the exact two-sided
binomial p-value under "either is as likely to be better"; the tables print the number of
tasks beside every p-value.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from pydantic import Field

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.report.bootstrap import Episodes, cell_estimates, multiplicities, percentile_interval
from vlm_bench.report.groups import OVERALL, SUITES, Grouping
from vlm_bench.report.report_options import BOOT_SEED, CI_LEVEL, N_BOOT
from vlm_bench.report.summary import BOTH, By, by_columns, is_percent, system_order, system_rows
from vlm_bench.types.base import Frozen

EPISODE = ["task_id", "seed", "instruction"]


class PairedComparison(Frozen):
    """A − B on one metric over the episodes both answered."""

    a: str = Field(description="System A (its ``by`` values joined by '/').")
    b: str = Field(description="System B, the reference.")
    metric: str = Field(description="Metric compared (Succ and exec_success in percent).")
    n: int = Field(ge=0, description="Common episodes.")
    n_tasks: int = Field(ge=0, description="Tasks they cover.")
    diff: float = Field(description="A − B, the table's overall estimator on the differences.")
    lo: float = Field(description="Lower end of the bootstrap interval (NaN: too few tasks).")
    hi: float = Field(description="Upper end of the bootstrap interval.")
    n_better: int = Field(ge=0, description="Tasks where A scores higher (mean over episodes).")
    n_worse: int = Field(ge=0, description="Tasks where A scores lower.")
    n_tied: int = Field(ge=0, description="Tasks with equal mean scores.")
    p_sign: float = Field(
        ge=0, le=1, description="Exact two-sided sign-test p-value over tasks (n_tasks units)."
    )


def sign_test(n_better: int, n_worse: int) -> float:
    """Exact two-sided sign test: P(a split at least this uneven) under Binomial(n, 1/2).

    Ties are left out before calling. ``sign_test(0, 0) == 1``.
    """
    n = n_better + n_worse
    if n == 0:
        return 1.0
    k = min(n_better, n_worse)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2**n  # exact: integers, then one division
    return float(min(1.0, 2.0 * tail))


def metric_values(frame: pd.DataFrame, metric: str) -> pd.Series:
    """An episode column as floats (``Succ`` True/False as 1/0).

    Raises:
        ConfigError: No such column, or one that is not numeric.
    """
    if metric not in frame.columns:
        raise ConfigError(f"no episode column {metric!r} to compare on")
    try:
        return frame[metric].astype(float)
    except (TypeError, ValueError):
        raise ConfigError(f"cannot compare on {metric!r}: not a numeric column") from None


def find_system(frame: pd.DataFrame, by: By, name: object) -> tuple[object, ...]:
    """The system (tuple of ``by`` values) called ``name``: a value, a tuple, or for several
    ``by`` columns their values joined by '/' (``"uav,overhead/448"``).

    Raises:
        UnknownNameError: No such system (lists them).
    """
    keys = by_columns(by)
    systems = system_order(frame, keys)
    if isinstance(name, str) and len(keys) > 1:
        name = tuple(name.split("/"))
    wanted = tuple(name) if isinstance(name, tuple | list) else (name,)
    for system in systems:
        if tuple(str(v) for v in system) == tuple(str(v) for v in wanted):
            return system
    raise UnknownNameError(
        " / ".join(keys), "/".join(map(str, wanted)), ["/".join(map(str, s)) for s in systems]
    )


def paired_comparison(
    frame: pd.DataFrame,
    a: object,
    b: object,
    metric: str = "S_total",
    by: By = "run",
    grouping: Grouping = SUITES,
    n_boot: int = N_BOOT,
    seed: int = BOOT_SEED,
    level: float = CI_LEVEL,
) -> PairedComparison:
    """Compare system ``a`` with ``b`` on their common answered episodes.

    Args:
        frame: Episode rows of both systems (:func:`vlm_bench.report.load`).
        a: System A: a value of ``by`` (a tuple for several columns).
        b: System B, the reference.
        metric: A numeric episode column (``S_total``, ``Succ``, ``S_loc``, ``exec_success``).
        by: Column(s) naming the systems; ``run`` by default.
        grouping: Groups of the overall estimator and the bootstrap's strata.
        n_boot: Bootstrap replicates. seed: Resampling seed. level: Interval coverage.

    Raises:
        UnknownNameError: ``a`` or ``b`` is no system of the frame (lists them).
        ConfigError: ``metric`` is no numeric episode column.
    """
    keys = by_columns(by)
    frame = grouping.assign(frame)
    ok = frame[(frame["status"] == "ok") & metric_values(frame, metric).notna()]
    sys_a, sys_b = find_system(frame, keys, a), find_system(frame, keys, b)
    rows_a = system_rows(ok, keys, sys_a)[[*EPISODE, grouping.column, metric]]
    rows_b = system_rows(ok, keys, sys_b)[[*EPISODE, metric]]
    both = rows_a.merge(rows_b, on=EPISODE, suffixes=("_a", "_b"))
    scale = 100.0 if is_percent(metric) else 1.0
    diff = (metric_values(both, f"{metric}_a") - metric_values(both, f"{metric}_b")) * scale
    both = both.assign(d=diff.to_numpy())
    per_task = both.groupby("task_id", sort=False)["d"].mean()
    better, worse = int((per_task > 0).sum()), int((per_task < 0).sum())
    result = {
        "a": "/".join(map(str, sys_a)),
        "b": "/".join(map(str, sys_b)),
        "metric": metric,
        "n": len(both),
        "n_tasks": int(both["task_id"].nunique()),
        "n_better": better,
        "n_worse": worse,
        "n_tied": len(per_task) - better - worse,
        "p_sign": sign_test(better, worse),
    }
    if both.empty:
        return PairedComparison(**result, diff=math.nan, lo=math.nan, hi=math.nan)
    episodes = Episodes.of(both, "d", grouping.column)
    key = (BOTH if both["instruction"].nunique() > 1 else both["instruction"].iloc[0], OVERALL)
    point = cell_estimates(episodes, np.ones((1, len(episodes.tasks))), grouping.order)[key]
    reps = cell_estimates(
        episodes,
        multiplicities(episodes.strata, n_boot, np.random.default_rng(seed)),
        grouping.order,
    )[key]
    counts = pd.Series(episodes.strata).value_counts()
    lo, hi = percentile_interval(reps, level) if counts.min() >= 2 else (math.nan, math.nan)
    return PairedComparison(**result, diff=float(point[0]), lo=lo, hi=hi)


def paired_table(
    frame: pd.DataFrame,
    reference: object,
    metrics: Sequence[str] = ("S_total", "Succ"),
    by: By = "run",
    grouping: Grouping = SUITES,
    n_boot: int = N_BOOT,
    seed: int = BOOT_SEED,
    level: float = CI_LEVEL,
) -> pd.DataFrame:
    """Every other system against ``reference``, one row per system × metric
    (the fields of :class:`PairedComparison`)."""
    keys = by_columns(by)
    ref = find_system(frame, keys, reference)
    rows = [
        paired_comparison(
            frame, system, ref, metric, keys, grouping, n_boot, seed, level
        ).model_dump()
        for system in system_order(frame, keys)
        if system != ref
        for metric in metrics
    ]
    return pd.DataFrame(rows, columns=list(PairedComparison.model_fields))
