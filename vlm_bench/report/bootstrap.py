"""Bootstrap confidence intervals of the table's cells, clustered by task.

Episodes of one task share its scene, objects and instruction (seeds move the layout, the two
instruction variants share a scene), so they are not independent draws: the bootstrap resamples
*tasks* with replacement and keeps every episode of a drawn task. Tasks are resampled within
their table group (suite or paper column), so every replicate has the table's structure. A
replicate's cells, overall and ``both`` values are computed exactly as the table computes them
(:mod:`vlm_bench.report.summary`); the point estimate is the table's value. The interval is the
percentile interval of ``n_boot`` replicates; a seed makes it reproducible. A value that rests
on a group with a single task has no interval (NaN): resampling one task cannot vary it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.groups import OVERALL, SUITES, Grouping
from vlm_bench.report.report_options import BOOT_SEED, CI_LEVEL, N_BOOT
from vlm_bench.report.summary import BOTH, By, by_columns, is_percent

CI_METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ")
"""Metrics that get intervals by default (``exec_success`` and ``S_task`` too when present)."""

Cells = dict[tuple[str, str], np.ndarray]
"""(instruction, group) → one estimate per replicate."""


@dataclass(frozen=True)
class Episodes:
    """One system's answered episodes of one metric, as arrays."""

    task: np.ndarray
    """Index of each episode's task in :attr:`tasks`."""
    instruction: np.ndarray
    group: np.ndarray
    value: np.ndarray
    tasks: list[str]
    strata: np.ndarray
    """Group of each task (tasks are resampled within it)."""

    @classmethod
    def of(cls, rows: pd.DataFrame, metric: str, group_column: str) -> Episodes:
        """Episodes with a value of ``metric``; ``Succ`` and ``exec_success`` in percent."""
        rows = rows[rows[metric].notna()]
        value = rows[metric].astype(float).to_numpy() * (100.0 if is_percent(metric) else 1.0)
        codes, tasks = pd.factorize(rows["task_id"])
        strata = rows.groupby("task_id", sort=False)[group_column].first().reindex(tasks)
        return cls(
            task=codes,
            instruction=rows["instruction"].to_numpy(),
            group=rows[group_column].to_numpy(),
            value=value,
            tasks=list(tasks),
            strata=strata.to_numpy(),
        )


def multiplicities(strata: np.ndarray, n_boot: int, rng: np.random.Generator) -> np.ndarray:
    """``(n_boot, tasks)``: how often each task is drawn, resampling within each stratum."""
    out = np.zeros((n_boot, len(strata)))
    for stratum in dict.fromkeys(strata.tolist()):
        idx = np.flatnonzero(strata == stratum)
        out[:, idx] = rng.multinomial(len(idx), np.full(len(idx), 1.0 / len(idx)), size=n_boot)
    return out


def _strict_mean(arrays: Sequence[np.ndarray]) -> np.ndarray:
    # Like the table: a missing cell makes the mean missing (no partial overall).
    out: np.ndarray = np.mean(np.stack(arrays), axis=0)
    return out


def cell_estimates(episodes: Episodes, weights: np.ndarray, order: Sequence[str]) -> Cells:
    """Every table value of one system and metric, one per row of ``weights``.

    Cells are weighted episode means; overall is the mean of the row's group cells; ``both``
    averages the instruction cells of each group (and its overall, the groups).
    """
    cells: Cells = {}
    instructions = list(dict.fromkeys(episodes.instruction.tolist()))
    groups = [g for g in order if g in set(episodes.group.tolist())]
    for instruction in instructions:
        for group in groups:
            mask = (episodes.instruction == instruction) & (episodes.group == group)
            if not mask.any():
                continue
            w = weights[:, episodes.task[mask]]
            with np.errstate(invalid="ignore", divide="ignore"):
                cells[(instruction, group)] = (w @ episodes.value[mask]) / w.sum(axis=1)
    for instruction in instructions:
        row = [cells.get((instruction, g)) for g in groups]
        cells[(instruction, OVERALL)] = (
            _strict_mean([r for r in row if r is not None])
            if all(r is not None for r in row)
            else np.full(len(weights), np.nan)
        )
    if len(instructions) > 1:
        for group in [*groups, OVERALL]:
            found = [cells.get((i, group)) for i in instructions]
            if all(f is not None for f in found):
                cells[(BOTH, group)] = _strict_mean([f for f in found if f is not None])
    return cells


def percentile_interval(replicates: np.ndarray, level: float) -> tuple[float, float]:
    """The central ``level`` percentile interval of the finite replicates (NaN if none)."""
    finite = replicates[np.isfinite(replicates)]
    if finite.size == 0:
        return float("nan"), float("nan")
    tail = 50.0 * (1.0 - level)
    lo, hi = np.percentile(finite, [tail, 100.0 - tail])
    return float(lo), float(hi)


def bootstrap_cis(
    frame: pd.DataFrame,
    by: By = "model",
    grouping: Grouping = SUITES,
    metrics: Sequence[str] | None = None,
    n_boot: int = N_BOOT,
    seed: int = BOOT_SEED,
    level: float = CI_LEVEL,
) -> pd.DataFrame:
    """Percentile intervals of every table value, clustered by task (see the module docstring).

    Args:
        frame: Episode rows (:func:`vlm_bench.report.load`).
        by: Column(s) naming a row's system.
        grouping: Column groups (suites or the paper's columns).
        metrics: Metrics; default :data:`CI_METRICS`, plus ``exec_success`` and ``S_task``
            when some episode was executed.
        n_boot: Bootstrap replicates.
        seed: Seed of the resampling; each system uses a generator seeded with it.
        level: Coverage of the interval (0.95 = 2.5th to 97.5th percentile).

    Returns:
        One row per system × instruction × group (overall and ``both`` included) × metric:
        ``by`` columns, ``instruction``, the grouping's column, ``metric``, ``value`` (the
        table's), ``lo``, ``hi``, ``n`` (episodes) and ``n_tasks``.
    """
    keys, column = by_columns(by), grouping.column
    frame = grouping.assign(frame)
    ok = frame[frame["status"] == "ok"]
    if metrics is None:
        executed = "exec_success" in ok.columns and ok["exec_success"].notna().any()
        metrics = (*CI_METRICS, "exec_success", "S_task") if executed else CI_METRICS
    rows: list[dict[str, object]] = []
    for system, mine in ok.groupby(keys, sort=False, dropna=False):
        for metric in metrics:
            episodes = Episodes.of(mine, metric, column)
            if not len(episodes.value):
                continue
            rng = np.random.default_rng(seed)
            point = cell_estimates(episodes, np.ones((1, len(episodes.tasks))), grouping.order)
            reps = cell_estimates(
                episodes, multiplicities(episodes.strata, n_boot, rng), grouping.order
            )
            for (instruction, group), value in point.items():
                counts = _counts(episodes, instruction, group)
                lo, hi = percentile_interval(reps[(instruction, group)], level)
                if counts.pop("fewest") < 2:  # one task: resampling cannot vary it
                    lo = hi = float("nan")
                rows.append(
                    {
                        **dict(zip(keys, system, strict=True)),
                        "instruction": instruction,
                        column: group,
                        "metric": metric,
                        "value": float(value[0]),
                        "lo": lo,
                        "hi": hi,
                        **counts,
                    }
                )
    columns = [*keys, "instruction", column, "metric", "value", "lo", "hi", "n", "n_tasks"]
    return pd.DataFrame(rows, columns=columns)


def _counts(episodes: Episodes, instruction: str, group: str) -> dict[str, int]:
    mask = np.ones(len(episodes.value), dtype=bool)
    if instruction != BOTH:
        mask &= episodes.instruction == instruction
    if group != OVERALL:
        mask &= episodes.group == group
    tasks = set(episodes.task[mask].tolist())
    per_group = {g: sum(episodes.strata[t] == g for t in tasks) for g in episodes.group[mask]}
    return {"n": int(mask.sum()), "n_tasks": len(tasks), "fewest": min(per_group.values())}
