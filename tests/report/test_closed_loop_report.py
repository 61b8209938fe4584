"""Closed-loop report numbers: Succ@k, intervals, recovery by trigger, extra steps, the plot."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from vlm_bench.report.closed_loop import (
    loop_sections,
    plot_succ_at_k,
    recovery_by_trigger,
    succ_at_k,
)


def _loops() -> pd.DataFrame:
    rows = [
        # task, succ_at (k = 0..2), trigger, steps executed, GT steps
        ("a", (1, 1, 1), None, 3, 3),
        ("a", (0, 1, 1), "slipped", 6, 3),
        ("b", (0, 0, 1), "out_of_reach", 9, 4),
        ("b", (0, 0, 0), "slipped", 8, 4),
    ]
    return pd.DataFrame(
        [
            {
                "run": "r",
                "instruction": "explicit",
                "task_id": task,
                "rounds_used": 1 + sum(1 for s in succ if not s) if succ[-1] else 3,
                "recovered": succ[0] == 0 and succ[-1] == 1,
                "trigger": trigger,
                "steps_executed": steps,
                "gt_steps": gt,
                **{f"succ_at_{k}": float(s) for k, s in enumerate(succ)},
            }
            for task, succ, trigger, steps, gt in rows
        ]
    )


def test_succ_at_k_is_the_share_succeeded_within_k_replans() -> None:
    curve = succ_at_k(_loops(), n_boot=200, seed=1)
    assert list(curve["k"]) == [0, 1, 2]
    assert list(curve["value"]) == pytest.approx([25.0, 50.0, 75.0])
    assert (curve["lo"] <= curve["value"]).all() and (curve["value"] <= curve["hi"]).all()
    assert set(curve["n"]) == {4}


def test_recovery_by_the_failure_that_triggered_the_replan() -> None:
    table = recovery_by_trigger(_loops()).set_index("trigger")
    assert table.loc["slipped", ["failed", "recovered"]].tolist() == [2, 1]
    assert table.loc["slipped", "rate"] == pytest.approx(50.0)
    assert table.loc["slipped", "extra_steps"] == pytest.approx(3.0)  # 6 run, GT 3
    assert table.loc["out_of_reach", "extra_steps"] == pytest.approx(5.0)


def test_sections_and_plot(tmp_path: Path) -> None:
    curve = succ_at_k(_loops(), n_boot=50)
    sections = loop_sections(_loops(), curve)
    assert [s.title for s in sections] == ["Closed loop", "Closed-loop recovery"]
    assert list(sections[0].frame.columns[2:5]) == ["Succ@0", "Succ@1", "Succ@2"]
    assert loop_sections(pd.DataFrame(), curve) == []
    path = plot_succ_at_k(curve, tmp_path / "succ.png")
    assert path.read_bytes().startswith(b"\x89PNG")
