"""Execution never averaged over a silent subset: a cell whose episodes were only partly
executed (a ``--by`` row pooling an executing and a planning-only run) shows the executed count
beside its Exec and Task values, and the CSV and Parquet carry ``n_executed``."""

from __future__ import annotations

import importlib.util
import io
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd
import pytest

from vlm_bench.report import build_report, load, render_tables, report_options, summary_long

if TYPE_CHECKING:
    from tests.conftest import Cli

BY = ("views", "resolution")


@pytest.fixture
def runs(
    tmp_path: Path,
    make_record: Callable[..., Any],
    make_execution: Callable[..., Any],
    make_run: Callable[..., Path],
) -> list[str]:
    """Two runs with the same views and resolution: ``exec`` executed one episode per task,
    ``plan`` (planning only) answered two more of the first task; the second task's cell is
    executed throughout."""
    r, ok = make_record, make_execution(True, 100.0)
    executed = [
        r("m", "standard_pick_place", 0, "explicit", 90.0, executed=ok, run="exec"),
        r("m", "tower_stacking", 0, "explicit", 90.0, executed=ok, run="exec"),
    ]
    planned = [r("m", "standard_pick_place", s, "explicit", 50.0, run="plan") for s in (1, 2)]
    return [
        str(make_run(tmp_path / "exec", executed, execute=True)),
        str(make_run(tmp_path / "plan", planned, execute=False)),
    ]


def test_long_summary_counts_the_executed_episodes(runs: list[str]) -> None:
    long = summary_long(load(*runs), list(BY)).set_index("suite")
    assert (long.loc["base_manipulation", "n"], long.loc["base_manipulation", "n_executed"]) == (
        3,
        1,
    )
    assert long.loc["long_horizon", "n_executed"] == long.loc["long_horizon", "n"] == 1
    assert (long.loc["overall", "n_executed"], long.loc["overall", "n"]) == (2, 4)


def test_tables_print_the_count_beside_partly_executed_values(runs: list[str]) -> None:
    options = report_options(
        runs=tuple(runs), by=BY, format="markdown", grouping="suites", stats=False
    )
    text = render_tables(build_report(options))
    assert isinstance(text, str)
    header, row = (
        [c.strip() for c in line.split("|")[1:-1]]
        for line in text.splitlines()
        if line.startswith("| ")
    )
    cell = dict(zip(header, row, strict=True))
    assert cell["BM Exec"] == "100.0 (1/3)" and cell["BM Task"] == "100.0 (1/3)"
    assert cell["LH Exec"] == "100.0"  # executed throughout: no count
    assert cell["Overall Exec"] == "100.0 (2/4)"
    assert "cover only the e of the cell's n answered episodes" in text
    latex = render_tables(build_report(options.model_copy(update={"format": "latex"})))
    assert isinstance(latex, str)
    assert r"100.0\,{\scriptsize(1/3)}" in latex


def test_terminal_shows_the_count(cli: Cli, runs: list[str]) -> None:
    out = cli.invoke("report", *runs, "--by", ",".join(BY), "--no-stats", "--grouping", "suites")
    assert "(1/3)" in out and "(2/4)" in out


def test_csv_and_parquet_carry_n_executed(runs: list[str], tmp_path: Path) -> None:
    options = report_options(runs=tuple(runs), by=BY, format="csv", stats=False)
    table = pd.read_csv(io.StringIO(str(render_tables(build_report(options)))))
    overall = table[(table.grouping == "suites") & (table.group == "overall")].iloc[0]
    assert (overall.n_executed, overall.n) == (2, 4)
    if importlib.util.find_spec("pyarrow") is None:
        pytest.skip("pyarrow is not installed")
    out = tmp_path / "t.parquet"
    options = options.model_copy(update={"format": "parquet", "out": out})
    out.write_bytes(render_tables(build_report(options)))  # type: ignore[arg-type]
    assert "n_executed" in pd.read_parquet(out).columns


def test_the_interval_table_counts_the_executed_episodes_too(runs: list[str]) -> None:
    options = report_options(runs=tuple(runs), by=BY, format="markdown", n_boot=100)
    text = render_tables(build_report(options))
    assert isinstance(text, str)
    section = text.split("## Overall with confidence intervals")[1].split("##")[0]
    assert "100.0 (2/4)" in section
