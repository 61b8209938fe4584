"""Execution columns of the summary: hand-computed cells, unexecuted plans, mixed runs."""

from __future__ import annotations

import math
from collections.abc import Callable

import pandas as pd
import pytest

from vlm_bench.report import EXEC_VALUES, records_frame, summary_long, summary_markdown
from vlm_bench.report.tables import summary_rich
from vlm_bench.types.execution import ExecutionSummary, VlaScores
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.scores import PlanScores


def _execution(success: bool, s_task: float, vla: float) -> ExecutionSummary:
    return ExecutionSummary(
        exec_success=success,
        steps_ok=success,
        n_steps_done=1,
        s_task=s_task,
        scores=VlaScores(s_pos=vla, s_arm=vla / 2, s_safe=100.0, s_task=s_task, total=vla),
        sim_time_s=1.0,
        wall_time_s=0.1,
    )


@pytest.fixture
def rec(make_scores: Callable[..., PlanScores]) -> Callable[..., EpisodeRecord]:
    """A record of run ``run`` (every planning metric 100) with ``execution``; ``ok=False``:
    a backend error."""

    def build(
        run: str,
        suite: str,
        seed: int,
        variant: str,
        execution: ExecutionSummary | None,
        ok: bool = True,
    ) -> EpisodeRecord:
        return EpisodeRecord(
            run_id=run,
            key=f"{suite}_t/{seed}/{variant}",
            task_id=f"{suite}_t",
            suite=suite,
            seed=seed,
            variant=variant,
            model=run,
            scores=make_scores(100.0, 100.0, 100.0, 100.0, succ=True) if ok else None,
            status="ok" if ok else "error",
            execution=execution,
        )

    return build


def _cell(long: pd.DataFrame, model: str, instruction: str, suite: str) -> pd.Series:
    hit = long[(long.model == model) & (long.instruction == instruction) & (long.suite == suite)]
    assert len(hit) == 1, hit
    return hit.iloc[0]


@pytest.fixture
def frame(rec: Callable[..., EpisodeRecord]) -> pd.DataFrame:
    # Base: a success (S_task 100, VLA 80) and an output with no plan (not executed).
    # Long horizon: a failure (S_task 50, VLA 40) and a backend error (left out).
    return records_frame(
        [
            rec("m", "base_manipulation", 0, "explicit", _execution(True, 100.0, 80.0)),
            rec("m", "base_manipulation", 1, "explicit", None),
            rec("m", "long_horizon", 0, "explicit", _execution(False, 50.0, 40.0)),
            rec("m", "long_horizon", 1, "explicit", None, ok=False),
        ],
        {"m": True},
    )


def test_exec_cells_count_unexecuted_plans_as_zero(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    base = _cell(long, "m", "explicit", "base_manipulation")
    assert (base.exec_success, base.S_task, base.S_pos, base.S_arm) == (50.0, 50.0, 40.0, 20.0)
    assert (base.S_safe, base.VLA_total, base.n) == (50.0, 40.0, 2)
    lh = _cell(long, "m", "explicit", "long_horizon")
    assert (lh.exec_success, lh.S_task, lh.VLA_total, lh.n, lh.n_error) == (0.0, 50.0, 40.0, 1, 1)
    overall = _cell(long, "m", "explicit", "overall")  # unweighted mean of the suite cells
    assert (overall.exec_success, overall.S_task, overall.VLA_total) == (25.0, 50.0, 40.0)


def test_tables_show_exec_and_task_only(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    text = summary_markdown(long)
    header = text.splitlines()[0]
    assert "BM Exec" in header and "Overall Task" in header and "S_pos" not in header
    assert "Exec = execution success" in text
    wide = summary_rich(long, width=None)
    assert any("Exec" in str(col.header) for col in wide.columns)
    narrow = summary_rich(long, width=60)
    assert [str(c.header) for c in narrow.columns][-3:] == ["Exec", "Task", "n"]


def test_runs_without_execution_have_no_exec_columns(rec: Callable[..., EpisodeRecord]) -> None:
    frame = records_frame([rec("m", "base_manipulation", 0, "explicit", None)], {"m": False})
    assert frame[list(EXEC_VALUES)].isna().all().all()
    long = summary_long(frame)
    assert not set(EXEC_VALUES) & set(long.columns)
    assert "Exec" not in summary_markdown(long)


def test_comparing_an_executing_run_with_a_planning_only_run(
    rec: Callable[..., EpisodeRecord],
) -> None:
    frame = records_frame(
        [
            rec("a", "base_manipulation", 0, "explicit", _execution(True, 100.0, 90.0)),
            rec("b", "base_manipulation", 0, "explicit", None),
        ],
        {"a": True, "b": False},
    )
    long = summary_long(frame)
    assert _cell(long, "a", "explicit", "overall").exec_success == 100.0
    assert math.isnan(_cell(long, "b", "explicit", "overall").exec_success)


def test_executing_runs_are_guessed_without_manifests(rec: Callable[..., EpisodeRecord]) -> None:
    frame = records_frame(
        [
            rec("a", "base_manipulation", 0, "explicit", _execution(False, 0.0, 10.0)),
            rec("a", "base_manipulation", 1, "explicit", None),
            rec("b", "base_manipulation", 0, "explicit", None),
        ]
    )
    assert frame.exec_success.tolist()[:2] == [False, False]
    assert frame.exec_success.isna().iloc[2]
