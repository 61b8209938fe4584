"""The diagnostics (move ratio, precision-aware S_loc), where the episode frame has them, appear
in every table as diagnostic columns or a LaTeX note; the paper's S_loc stays the headline."""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path

import pandas as pd
import pytest
from rich.console import Console

from vlm_bench.report import load, summary_long, summary_markdown, summary_rich
from vlm_bench.report.groups import SUITES
from vlm_bench.report.latex import summary_latex, table_notes
from vlm_bench.report.latex_compact import compact_latex
from vlm_bench.types.records import EpisodeRecord


@pytest.fixture
def frame(
    tmp_path: Path, make_record: Callable[..., EpisodeRecord], make_run: Callable[..., Path]
) -> pd.DataFrame:
    records = [
        make_record("oracle", "standard_pick_place", seed, v, 80.0)
        for seed in (0, 1)
        for v in ("explicit", "implicit")
    ]
    loaded = load(make_run(tmp_path / "run", records))
    # Columns the episode frame gets from the scores (predicted / GT UAV moves, the S_loc that
    # charges extra moves): two extra moves on seed 1.
    return loaded.assign(
        Move_ratio=[1.0 if s == 0 else 3.0 for s in loaded["seed"]],
        S_loc_prec=[80.0 if s == 0 else 40.0 for s in loaded["seed"]],
    )


def test_summary_carries_the_diagnostics_beside_the_papers_loc(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    overall = long[(long["suite"] == "overall") & (long["instruction"] == "both")].iloc[0]
    assert overall["Move_ratio"] == pytest.approx(2.0)
    assert overall["S_loc_prec"] == pytest.approx(60.0)
    assert overall["S_loc"] == pytest.approx(80.0)  # the headline is unchanged
    csv = pd.read_csv(io.StringIO(long.to_csv(index=False)))
    assert {"Move_ratio", "S_loc_prec"} <= set(csv.columns)


def test_terminal_and_markdown_show_them_as_diagnostic_columns(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    md = summary_markdown(long)
    assert "Mv/GT" in md and "LocP" in md and "Diagnostics" in md and "2.00" in md
    console = Console(width=300, record=True)
    console.print(summary_rich(long, width=300))
    text = console.export_text()
    assert "Mv/GT" in text and "LocP" in text


def test_latex_notes_them_once(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    notes = table_notes(long, "model", SUITES)
    compact = compact_latex(
        long, "model", SUITES, ["S_total"], "column", caption="c", label="l", notes=notes
    )
    for text in (summary_latex(long), compact):
        assert text.count("Diagnostics") == 1
        assert "oracle 2.00 / 60.0" in text
        assert "Mv/GT" not in text  # a note, not a column of the paper's table
