"""Small things a reader would trip over: piped tables cut at 80 columns, ``--paired`` with no
other row, bars that read "not executed" as 0, sector counts, the episode frame's types."""

from __future__ import annotations

import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd
import pytest

from vlm_bench.report import build_report, load, render_tables, report_options

if TYPE_CHECKING:
    from tests.conftest import Cli

TASKS = ("standard_pick_place", "tower_stacking")


@pytest.fixture
def runs(
    tmp_path: Path,
    make_record: Callable[..., Any],
    make_execution: Callable[..., Any],
    make_run: Callable[..., Path],
) -> list[str]:
    """``planner`` (planning only) and ``executor`` (executes), 2 tasks x 2 seeds x 2
    instructions; the first episode of ``planner`` has tags and token counts."""
    r, ok = make_record, make_execution(True, 100.0)
    plans = [
        r(
            "planner",
            t,
            s,
            v,
            50.0,
            run="planner",
            tags=("wrong_direction", "no_json") if not (s or i) else (),
        )
        for i, t in enumerate(TASKS)
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]
    plans[0] = plans[0].model_copy(update={"prompt_tokens": 1200, "completion_tokens": 80})
    executes = [
        r("executor", t, s, v, 70.0, run="executor", executed=ok)
        for t in TASKS
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]
    return [
        str(make_run(tmp_path / "planner", plans, execute=False)),
        str(make_run(tmp_path / "executor", executes, execute=True)),
    ]


def test_piped_terminal_output_is_not_cut_at_80_columns(cli: Cli, runs: list[str]) -> None:
    done = subprocess.run(
        cli.command("report", *runs, "--no-stats", "--grouping", "suites"),
        capture_output=True, text=True, timeout=120, check=True, env=None,
    )  # fmt: skip
    assert "…" not in done.stdout
    assert "explicit" in done.stdout and "implicit" in done.stdout
    assert max(len(line) for line in done.stdout.splitlines()) > 80


def test_paired_with_no_other_row_says_so(runs: list[str]) -> None:
    options = report_options(runs=(runs[0],), paired="planner", format="markdown", stats=False)
    text = render_tables(build_report(options))
    assert isinstance(text, str)
    assert "## Paired comparison with planner" in text and "no other row" in text


def test_bars_say_not_executed_instead_of_zero(runs: list[str]) -> None:
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from vlm_bench.report.plots import _bars, overall_cis

    report = build_report(
        report_options(runs=tuple(runs), n_boot=100, stats=False, plots=Path("."))
    )
    table = overall_cis(report.cis["suites"], ["model"], "suite")
    fig, ax = plt.subplots()
    _bars(ax, table, ["model"], ["Tot", "Exec"], ["S_total", "exec_success"])
    notes = [t.get_text() for t in ax.texts]
    plt.close(fig)
    assert notes == ["not executed"]  # the planner's Exec; the executor's 100 is a bar


def test_sector_labels_count_episodes_and_tasks(runs: list[str]) -> None:
    from vlm_bench.report.plots import sector_labels

    frame = load(*runs)
    sector = frame["first_move"].dropna().iloc[0]
    (label,) = sector_labels(frame, [sector])
    # Both tasks start with the same GT move in the fixture: 2 tasks x 2 seeds x 2 instructions.
    assert label == f"{sector}\n8 ep.\n2 tasks"


def test_episode_frame_types(runs: list[str], tmp_path: Path) -> None:
    frame = load(*runs)
    first = frame.iloc[0]
    assert first.error_tags == ["wrong_direction", "no_json"] and frame.iloc[2].error_tags == []
    assert str(frame["prompt_tokens"].dtype) == "Int64" and first.prompt_tokens == 1200
    assert frame["completion_tokens"].isna().sum() == len(frame) - 1
    # Outcomes are nullable booleans, the tables' percentages come from them.
    assert str(frame["Succ"].dtype) == str(frame["exec_success"].dtype) == "boolean"
    planner = frame[frame.model == "planner"]
    assert planner["exec_success"].isna().all()
    assert frame[frame.model == "executor"]["exec_success"].all()
    options = report_options(runs=tuple(runs), episodes=tmp_path / "e.csv", stats=False)
    from vlm_bench.report.make import write_outputs

    write_outputs(build_report(options))
    csv = pd.read_csv(tmp_path / "e.csv", keep_default_na=False)
    assert csv.iloc[0].error_tags == "wrong_direction,no_json"
