"""Closed-loop metrics (docs/design.md#closed-loop): Succ@k with bootstrap intervals, recovery by
the failure that triggered the first replan, extra steps per recovery, and the Succ@k plot.

Read from the records of closed-loop runs (``record.loop``); open-loop runs add nothing here.
Succ@k is the percent of episodes whose task succeeded within rounds 0..k (Succ@0 is the
open-loop execution success); intervals resample tasks with replacement (task-clustered).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.bootstrap import percentile_interval
from vlm_bench.report.report_options import BOOT_SEED, CI_LEVEL, N_BOOT
from vlm_bench.report.sections import Section
from vlm_bench.report.text import with_ci
from vlm_bench.storage import RunPaths, latest_records
from vlm_bench.types.records import EpisodeRecord


def _row(run: str, record: EpisodeRecord) -> dict[str, Any] | None:
    loop = record.loop
    if loop is None or not record.ok:
        return None
    row: dict[str, Any] = {
        "run": run,
        "model": record.model,
        "key": record.key,
        "task_id": record.task_id,
        "instruction": record.variant,
        "rounds_used": loop.rounds_used,
        "recovered": loop.recovered,
        "trigger": loop.failure_codes[0],
        "steps_executed": loop.steps_executed,
        "gt_steps": len(record.gt_plan),
        "end": loop.end,
        "perturbations": sum(
            len(e.perturbations or ())
            for e in (record.execution, *(r.execution for r in record.rounds or ()))
            if e is not None
        ),
    }
    row.update({f"succ_at_{k}": float(ok) for k, ok in enumerate(loop.succ_at)})
    return row


def loop_frame(frame: pd.DataFrame) -> pd.DataFrame:
    """One row per closed-loop episode of the report's runs (empty: no closed-loop run)."""
    rows: list[dict[str, Any]] = []
    if frame.empty or "run_dir" not in frame.columns:
        return pd.DataFrame()
    for (run, run_dir), part in frame.groupby(["run", "run_dir"], sort=False):
        keys = set(part["key"])
        for record in latest_records(RunPaths(Path(run_dir)).records):
            row = _row(str(run), record) if record.key in keys else None
            if row is not None:
                rows.append(row)
    return pd.DataFrame(rows)


def _ks(loops: pd.DataFrame) -> list[int]:
    return sorted(int(c.rsplit("_", 1)[1]) for c in loops.columns if c.startswith("succ_at_"))


def succ_at_k(
    loops: pd.DataFrame, n_boot: int = N_BOOT, seed: int = BOOT_SEED, level: float = CI_LEVEL
) -> pd.DataFrame:
    """Succ@k per run and instruction with task-clustered bootstrap intervals (columns run,
    instruction, k, value, lo, hi, n)."""
    out: list[dict[str, Any]] = []
    rng = np.random.default_rng(seed)
    for (run, instruction), part in loops.groupby(["run", "instruction"], sort=False):
        tasks = sorted(set(part["task_id"]))
        by_task = {t: part[part["task_id"] == t] for t in tasks}
        draws = rng.integers(0, len(tasks), size=(n_boot, len(tasks)))
        for k in _ks(part):
            column = f"succ_at_{k}"
            sums = np.array([by_task[t][column].sum() for t in tasks])
            counts = np.array([by_task[t][column].count() for t in tasks])
            reps = 100.0 * sums[draws].sum(axis=1) / np.maximum(counts[draws].sum(axis=1), 1)
            lo, hi = percentile_interval(reps, level) if len(tasks) > 1 else (np.nan, np.nan)
            value = 100.0 * float(part[column].mean())
            out.append(
                {"run": run, "instruction": instruction, "k": k, "value": value}
                | {"lo": lo, "hi": hi, "n": int(part[column].count())}
            )
    return pd.DataFrame(out)


def recovery_by_trigger(loops: pd.DataFrame) -> pd.DataFrame:
    """Episodes that failed round 0, by run and the failure code that triggered the replan:
    how many, how many recovered, and the extra steps a recovery took (steps executed over
    all rounds minus the GT plan's steps, mean)."""
    failed = loops[loops["succ_at_0"] == 0.0]
    rows = []
    for (run, trigger), part in failed.groupby(["run", "trigger"], sort=True, dropna=False):
        won = part[part["recovered"]]
        extra = (won["steps_executed"] - won["gt_steps"]).mean() if len(won) else float("nan")
        rows.append(
            {
                "run": run,
                "trigger": trigger if isinstance(trigger, str) else "–",
                "failed": len(part),
                "recovered": len(won),
                "rate": 100.0 * len(won) / len(part),
                "extra_steps": float(extra),
            }
        )
    return pd.DataFrame(rows)


def loop_sections(loops: pd.DataFrame, curve: pd.DataFrame) -> list[Section]:
    """The report's "Closed loop" tables (none without closed-loop episodes)."""
    if loops.empty:
        return []
    rows = []
    for (run, instruction), part in curve.groupby(["run", "instruction"], sort=False):
        cells = part.sort_values("k")
        row: dict[str, object] = {"Run": run, "Instr.": instruction}
        for _, c in cells.iterrows():
            row[f"Succ@{int(c['k'])}"] = with_ci(c["value"], c["lo"], c["hi"])
        mine = loops[(loops["run"] == run) & (loops["instruction"] == instruction)]
        row["rounds"] = f"{mine['rounds_used'].mean():.2f}"
        row["n"] = int(cells["n"].iloc[0])
        rows.append(row)
    frame = pd.DataFrame(rows)
    numeric = tuple(c for c in frame.columns if c not in ("Run", "Instr."))
    sections = [
        Section(
            "Closed loop",
            "Succ@k: percent of episodes whose task succeeded within rounds 0..k (Succ@0 = "
            "open-loop execution success); task-clustered bootstrap intervals; rounds = mean "
            "rounds used.",
            frame,
            numeric,
        )
    ]
    recovery = recovery_by_trigger(loops)
    if not recovery.empty:
        shown = recovery.assign(
            rate=recovery["rate"].map(lambda v: f"{v:.1f}"),
            extra_steps=recovery["extra_steps"].map(lambda v: "–" if v != v else f"{v:.1f}"),
        ).rename(
            columns={
                "run": "Run",
                "trigger": "first failure",
                "rate": "recovered %",
                "extra_steps": "extra steps",
            }
        )
        sections.append(
            Section(
                "Closed-loop recovery",
                "Episodes that failed round 0, by the failure code that triggered the first "
                "replan; extra steps = steps executed over all rounds minus the GT plan's, "
                "mean over recovered episodes.",
                shown,
                ("failed", "recovered", "recovered %", "extra steps"),
            )
        )
    return sections


def plot_succ_at_k(curve: pd.DataFrame, path: Path) -> Path:
    """Succ@k against k, one line per run and instruction, with interval bands."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for (run, instruction), part in curve.groupby(["run", "instruction"], sort=False):
        cells = part.sort_values("k")
        ax.plot(cells["k"], cells["value"], marker="o", label=f"{run} ({instruction})")
        ax.fill_between(cells["k"], cells["lo"], cells["hi"], alpha=0.2)
    ax.set_xlabel("replans allowed (k)")
    ax.set_ylabel("Succ@k (%)")
    ax.set_ylim(-2, 102)
    ax.set_xticks(sorted(set(curve["k"])))
    ax.set_title("Closed loop: task success within k replans")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path
