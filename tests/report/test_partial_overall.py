"""An Overall only over the same groups: a run of one suite beside a run of all four gets a
partial Overall (marked, never bold, never best) and a warning naming the missing groups, in
every format."""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd
import pytest

from vlm_bench.report import build_report, load, render_tables, report_options, summary_long
from vlm_bench.report.summary import sort_systems

if TYPE_CHECKING:
    from tests.conftest import Cli

ALL = (
    "standard_pick_place",
    "target_color_yellow",
    "synonym_block_bin",
    "tower_stacking",
)
LONG_HORIZON = ("tower_stacking", "drawer_interaction")


@pytest.fixture
def runs(
    tmp_path: Path, make_record: Callable[..., Any], make_run: Callable[..., Path]
) -> list[str]:
    """``random`` over all four suites (seed 0, planning only) beside ``oracle`` on Long-Horizon
    only (like ``vlm-bench run --model oracle --suite lh``)."""
    r = make_record
    random = [r("random", t, 0, v, 20.0) for t in ALL for v in ("explicit", "implicit")]
    oracle = [
        r("oracle", t, 0, v, 100.0, succ=True)
        for t in LONG_HORIZON
        for v in ("explicit", "implicit")
    ]
    return [
        str(make_run(tmp_path / "random", random, execute=False)),
        str(make_run(tmp_path / "oracle", oracle, execute=False)),
    ]


def _overall(long: pd.DataFrame, model: str, instruction: str) -> pd.Series:
    rows = long[
        (long.model == model) & (long.instruction == instruction) & (long.suite == "overall")
    ]
    return rows.iloc[0]


def test_the_long_summary_names_the_missing_groups(runs: list[str]) -> None:
    long = summary_long(load(*runs))
    oracle = _overall(long, "oracle", "both")
    assert oracle.missing_groups == "base_manipulation,object_spatial,semantic_understanding"
    assert oracle.S_total == pytest.approx(100.0)  # kept, but marked partial
    assert _overall(long, "random", "both").missing_groups == ""
    # A partial Overall does not rank: the complete row comes first even when sorting by Tot.
    ranked = sort_systems(long, ascending=False)
    assert list(dict.fromkeys(ranked.model)) == ["random", "oracle"]


def test_markdown_marks_and_warns(runs: list[str]) -> None:
    text = render_tables(
        build_report(report_options(runs=tuple(runs), format="markdown", n_boot=100))
    )
    assert isinstance(text, str)
    assert "| oracle | both |" in text
    oracle = next(line for line in text.splitlines() if line.startswith("| oracle | both |"))
    assert oracle.rstrip(" |").endswith("†")
    assert "Partial Overall†: oracle has no episode in BM, OS, SU" in text
    assert "The paper's three columns" in text and "has no episode in BM, DI" in text
    assert text.count("Partial Overall†: oracle has") == 2  # one warning per grouping


def test_latex_never_bolds_a_partial_overall(runs: list[str]) -> None:
    text = render_tables(build_report(report_options(runs=tuple(runs), format="latex")))
    assert isinstance(text, str)
    suites = text.split(r"\end{table*}")[0]
    oracle = next(line for line in suites.splitlines() if "oracle" in line)
    overall = oracle.split("&")[-6:]
    assert all(r"\textbf" not in cell for cell in overall)
    assert r"100.0\textsuperscript{\dag}" in oracle
    # The complete row holds the best Overall (the partial 100.0 is not compared).
    random = next(line for line in suites.splitlines() if "random" in line)
    assert r"\textbf{20.0}" not in random  # a single complete row: no best to mark
    # One note for the whole table, in the table's type size, not a paragraph per row.
    assert suites.count("Partial Overall") == 1 and "(oracle: no BM, OS, SU)" in suites
    assert r"\parbox{\linewidth}{\scriptsize" in suites


def test_csv_carries_the_missing_groups_and_the_cli_warns(cli: Cli, runs: list[str]) -> None:
    csv = cli.invoke("report", *runs, "-f", "csv", "--no-stats")
    table = pd.read_csv(io.StringIO(csv.split("warning:")[0]), keep_default_na=False)
    oracle = table[(table.model == "oracle") & (table.group == "overall")]
    assert set(oracle.missing_groups) >= {"base_manipulation,object_spatial,semantic_understanding"}
    assert "warning: Partial Overall†: oracle has no episode in BM, OS, SU" in csv


def test_terminal_marks_and_warns(cli: Cli, runs: list[str]) -> None:
    out = cli.invoke("report", *runs, "--no-stats", "--grouping", "suites")
    assert "Partial Overall†: oracle has no episode in BM, OS, SU" in " ".join(out.split())
    assert "Overall†" in out
