"""Succ@k and the recovery rate of closed-loop runs in every table: summary.md/summary.csv,
``report -f csv/latex/markdown``, the terminal table, and ``run --loop closed``'s own table."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import pytest

from vlm_bench.report import summary_rich, write_summary
from vlm_bench.report.make import build_report, render_tables
from vlm_bench.report.report_options import report_options
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.rounds import LoopOutcome

if TYPE_CHECKING:
    from tests.conftest import Cli

OUTCOMES = {
    # task, seed: succ_at for k = 0..2
    ("standard_pick_place", 0): (True, True, True),
    ("standard_pick_place", 1): (False, True, True),
    ("tower_stacking", 0): (False, False, True),
    ("tower_stacking", 1): (False, False, False),
}


def _closed_run(
    tmp_path: Path,
    make_record: Callable[..., EpisodeRecord],
    make_run: Callable[..., Path],
    make_execution: Callable[..., object],
) -> Path:
    records = []
    for (task, seed), succ in OUTCOMES.items():
        loop = LoopOutcome(
            succ_at=succ,
            rounds_used=1 + succ.index(True) if any(succ) else 3,
            recovered=not succ[0] and succ[-1],
            failure_codes=tuple(None if s else "slipped" for s in succ),
            steps_executed=3,
            budget=9,
            end="success" if succ[-1] else "max_rounds",
        )
        record = make_record(
            "rules", task, seed, "explicit", 80.0, executed=make_execution(succ[0], 50.0)
        )
        records.append(record.model_copy(update={"loop": loop}))
    return make_run(tmp_path / "closed", records, execute=True, loop="closed", max_rounds=2)


def test_summary_files_carry_succ_at_k_and_recovery(
    tmp_path: Path,
    make_record,
    make_run,
    make_execution,  # type: ignore[no-untyped-def]
) -> None:
    run = _closed_run(tmp_path, make_record, make_run, make_execution)
    long = write_summary(run)
    csv = pd.read_csv(run / "summary.csv")
    overall = csv[(csv["suite"] == "overall")].iloc[0]
    # BM: 1 of 2 at k=0 and 2 of 2 at k=1; LH: 0, 0, 1 of 2 -> Overall = mean of the suites.
    assert overall["Succ@1"] == pytest.approx((100.0 + 0.0) / 2)
    assert overall["Succ@2"] == pytest.approx((100.0 + 50.0) / 2)
    # Recovered: BM 1 of its 1 failure, LH 1 of 2 -> mean of the suites' rates.
    assert overall["Recovered"] == pytest.approx((100.0 + 50.0) / 2)
    md = (run / "summary.md").read_text()
    assert "Succ@2" in md and "Rec" in md and "replans" in md
    from rich.console import Console

    console = Console(width=250, record=True)
    console.print(summary_rich(long, width=250))
    text = console.export_text()
    assert "Succ@1" in text and "Succ@2" in text and "Rec" in text


@pytest.mark.parametrize("fmt", ["csv", "latex", "markdown"])
def test_report_formats_carry_succ_at_k(
    tmp_path: Path,
    make_record,
    make_run,
    make_execution,
    fmt: str,  # type: ignore[no-untyped-def]
) -> None:
    run = _closed_run(tmp_path, make_record, make_run, make_execution)
    report = build_report(report_options(runs=(str(run),), format=fmt, stats=False))
    text = render_tables(report)
    assert isinstance(text, str)
    assert "Succ@1" in text and "Succ@2" in text
    if fmt == "csv":
        table = pd.read_csv(__import__("io").StringIO(text))
        assert {"Succ@1", "Succ@2", "Recovered"} <= set(table.columns)
    else:
        assert "Rec" in text


def test_run_closed_loop_prints_succ_at_k(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    args = cli.run_args(out, "oracle", ("container_geometry_bowl",), "0", "--resolution", "32")
    done = cli.run(*args, "--instruction", "explicit", "--loop", "closed", "--max-rounds", "1")
    assert done.returncode == 0, done.stderr
    assert "Succ@1" in done.stdout
    assert "Succ@1" in (out / "summary.csv").read_text().splitlines()[0]
