"""PNG plots of a report (matplotlib, the ``plots`` extra; imported only here).

* ``metrics.png``: grouped bars of every overall metric per system, with the bootstrap interval.
* ``radar.png``: the four planning metrics (Plan, Loc, Obj, Skill) of each system.
* ``loc_by_direction.png``: S_loc by the GT's first horizontal move (the eight sectors of the
  UAV body frame), where the paper finds the bottleneck; intervals clustered by task, each
  sector labelled with its episodes and tasks (the intervals' independent units).

A metric a system has no value of (execution in a run that does not execute plans) gets no bar
but a note ("not executed"), so that it cannot read as 0.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import MissingExtraError
from vlm_bench.report.bootstrap import bootstrap_cis
from vlm_bench.report.dataframe import EXEC_METRICS
from vlm_bench.report.groups import OVERALL, Grouping
from vlm_bench.report.summary import headline, partial_overalls, system_order, system_rows
from vlm_bench.report.tables import HEADERS, header
from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS

if TYPE_CHECKING:
    from vlm_bench.report.contents import Report

PLANNING = ("S_plan", "S_loc", "S_obj", "S_skill")
SECTORS = tuple(d.value for d in HORIZONTAL_DIRECTIONS)
_ALL = Grouping(name="all", column="_all", order=("all",), titles={"all": "All"}, short={})


def _pyplot() -> Any:
    try:
        import matplotlib
    except ImportError:
        raise MissingExtraError("matplotlib", "plots") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def overall_cis(cis: pd.DataFrame, by: list[str], column: str) -> pd.DataFrame:
    """Each system's overall intervals of its headline instruction (``both`` where it has it)."""
    return headline(cis[cis[column] == OVERALL], by)


def _name(system: tuple[object, ...]) -> str:
    return "/".join(str(v) for v in system)


def _bars(
    ax: Any,
    table: pd.DataFrame,
    by: list[str],
    labels: list[str],
    metrics: list[str],
    partial: dict[tuple[object, ...], str] | None = None,
    legend_at: float = -0.12,
) -> None:
    """Grouped bars; a system in ``partial`` (its Overall misses groups: the groups it lacks)
    gets hatched bars and a † legend entry naming them."""
    partial = partial or {}
    systems = system_order(table, by)
    width = 0.8 / max(len(systems), 1)
    x = np.arange(len(labels))
    for i, system in enumerate(systems):
        mine = system_rows(table, by, system).set_index("metric")
        value = np.array([mine["value"].get(m, np.nan) for m in metrics], dtype=float)
        lo = np.array([mine["lo"].get(m, np.nan) for m in metrics], dtype=float)
        hi = np.array([mine["hi"].get(m, np.nan) for m in metrics], dtype=float)
        at = x + (i - (len(systems) - 1) / 2) * width
        name = _name(system)
        lacks = partial.get(system)
        if lacks is not None:
            name += f" † partial Overall (no {lacks})"
        bars = ax.bar(at, np.nan_to_num(value), width, label=name, hatch="//" if lacks else None)
        for where, metric, v in zip(at, metrics, value, strict=True):
            if math.isnan(v):  # no bar: say why, so that it cannot read as 0
                why = "not executed" if metric in EXEC_METRICS else "no value"
                ax.text(where, 1.5, why, rotation=90, ha="center", va="bottom", fontsize=6,
                        color=bars.patches[0].get_facecolor())  # fmt: skip
        has = np.isfinite(lo) & np.isfinite(hi) & np.isfinite(value)
        if has.any():  # no whisker where a group has a single task (no interval)
            err = np.vstack([value[has] - lo[has], hi[has] - value[has]])
            ax.errorbar(
                at[has], value[has], yerr=err, fmt="none", ecolor="black", capsize=2, elinewidth=0.8
            )
    ax.set_xticks(x, labels)
    ax.set_ylim(0, 105)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(
        fontsize=8,
        ncols=min(len(systems), 4),
        loc="upper center",
        bbox_to_anchor=(0.5, legend_at),
        frameon=False,
    )


def plot_metrics(report: Report, path: Path) -> Path:
    """Grouped bars of the overall metrics with their intervals."""
    plt = _pyplot()
    by, g = list(report.options.by), report.groupings[0]
    table = overall_cis(report.cis[g.name], by, g.column)
    metrics = [m for m in HEADERS if m in set(table["metric"])]
    n_systems = len(system_order(table, by))
    fig, ax = plt.subplots(figsize=(max(6.0, 1.5 + 0.22 * len(metrics) * n_systems), 4.2))
    _bars(ax, table, by, [header(m) for m in metrics], metrics, _partial(report))
    ax.set_ylabel("score / %")
    ax.set_title(f"Overall ({g.name}), {round(report.options.level * 100)} % CI over tasks")
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def _partial(report: Report) -> dict[tuple[object, ...], str]:
    """Systems whose headline Overall misses groups, with the groups' short names."""
    by, g = list(report.options.by), report.groupings[0]
    long = report.tables[g.name]
    shown = headline(long[long[g.column] == OVERALL], by)
    heads = set(shown[[*by, "instruction"]].itertuples(index=False, name=None))
    return {
        tuple(key[:-1]): ", ".join(g.short.get(x, x) for x in groups)
        for key, groups in partial_overalls(long, by).items()
        if key in heads
    }


def plot_radar(report: Report, path: Path) -> Path:
    """The four planning metrics of each system on a radar."""
    plt = _pyplot()
    by, g = list(report.options.by), report.groupings[0]
    table = overall_cis(report.cis[g.name], by, g.column)
    angles = np.linspace(0, 2 * math.pi, len(PLANNING), endpoint=False)
    fig, ax = plt.subplots(figsize=(5.2, 5.2), subplot_kw={"projection": "polar"})
    for system in system_order(table, by):
        mine = system_rows(table, by, system).set_index("metric")
        values = np.array([mine["value"].get(m, np.nan) for m in PLANNING], dtype=float)
        closed = np.append(values, values[0])
        ax.plot(np.append(angles, angles[0]), closed, marker="o", label=_name(system))
        ax.fill(np.append(angles, angles[0]), np.nan_to_num(closed), alpha=0.08)
    ax.set_xticks(angles, [header(m) for m in PLANNING])
    ax.set_ylim(0, 100)
    ax.set_rlabel_position(45)
    ax.set_title("Planning metrics (overall)", pad=18)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.06), ncols=3, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def loc_by_direction(report: Report) -> pd.DataFrame:
    """S_loc per system and GT first-move sector (value, interval, n), long form."""
    by, options = list(report.options.by), report.options
    parts = []
    for sector in SECTORS:
        rows = report.frame[report.frame["first_move"] == sector].assign(_all="all")
        if rows.empty:
            continue
        cis = bootstrap_cis(rows, by, _ALL, ("S_loc",), options.n_boot, options.seed, options.level)
        parts.append(overall_cis(cis, by, "_all").assign(metric=sector))
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()


def sector_labels(frame: pd.DataFrame, sectors: list[str]) -> list[str]:
    """``front\n4 ep.\n2 tasks``: each sector with its distinct episodes (task, seed,
    instruction, over all systems) and tasks (the units the intervals resample), on lines of
    their own so that neighbouring labels never overlap."""
    episodes = frame.drop_duplicates(["task_id", "seed", "instruction"])
    counts = episodes["first_move"].value_counts()
    tasks = episodes.groupby("first_move")["task_id"].nunique()
    return [f"{s}\n{counts.get(s, 0)} ep.\n{tasks.get(s, 0)} tasks" for s in sectors]


def plot_loc_by_direction(report: Report, path: Path) -> Path:
    """Grouped bars of S_loc per first-move sector with task-clustered intervals."""
    plt = _pyplot()
    fig = loc_by_direction_figure(report)
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def loc_by_direction_figure(report: Report) -> Any:
    """The figure of :func:`plot_loc_by_direction` (laid out, not saved)."""
    plt = _pyplot()
    by = list(report.options.by)
    table = loc_by_direction(report)
    sectors = [s for s in SECTORS if not table.empty and s in set(table["metric"])]
    fig, ax = plt.subplots(figsize=(10, 4.6))
    if sectors:
        labels = sector_labels(report.frame, sectors)
        _bars(ax, table, by, labels, sectors, legend_at=-0.24)  # below three-line labels
        ax.tick_params(axis="x", labelsize=8)
    ax.set_ylabel("S_loc")
    ax.set_title("S_loc by the GT's first horizontal move (UAV body frame)")
    fig.tight_layout()
    return fig


def write_plots(report: Report, folder: Path) -> list[Path]:
    """Write the three plots into ``folder`` (created); returns their paths."""
    folder.mkdir(parents=True, exist_ok=True)
    return [
        plot_metrics(report, folder / "metrics.png"),
        plot_radar(report, folder / "radar.png"),
        plot_loc_by_direction(report, folder / "loc_by_direction.png"),
    ]
