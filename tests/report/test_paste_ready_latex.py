"""Paste-ready LaTeX for a two-column paper: the ``column`` layout fits ``\\columnwidth`` at
8 pt and the ``wide`` one a ``table*`` at 7 pt, unscaled, with no overfull box (compiled with
pdflatex where installed); ``--columns`` picks the metrics; notes come once."""

from __future__ import annotations

import re
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

from vlm_bench.errors import UnknownNameError
from vlm_bench.report import build_report, render_tables, report_options
from vlm_bench.types.records import EpisodeRecord

TASKS = ("standard_pick_place", "target_color_yellow", "synonym_block_bin", "tower_stacking")
"""One task of each suite."""
MODELS = ("qwen2.5-vl-7b", "glm-4.1v-9b-thinking", "openai//srv/models/tiny-llava-interleave")


@pytest.fixture
def runs(
    tmp_path: Path,
    make_record: Callable[..., EpisodeRecord],
    make_run: Callable[..., Path],
) -> list[str]:
    out = []
    for m, model in enumerate(MODELS):
        tasks = TASKS if m < 2 else TASKS[:1]  # the last one ran one suite: a partial Overall
        records = [
            make_record(model, task, seed, variant, 40.0 + 10 * m + t, succ=(seed + t) % 2 == 0)
            for t, task in enumerate(tasks)
            for seed in (0, 1)
            for variant in ("explicit", "implicit")
        ]
        out.append(str(make_run(tmp_path / f"run{m}", records)))
    return out


def _latex(runs: list[str], **options: object) -> str:
    text = render_tables(build_report(report_options(runs=tuple(runs), format="latex", **options)))
    assert isinstance(text, str)
    return text


def _compile(tmp_path: Path, document: str) -> str:
    """pdflatex's log of ``document`` (and a PNG of its page where pdftoppm exists)."""
    tex = tmp_path / "page.tex"
    tex.write_text(document)
    done = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    log = (tmp_path / "page.log").read_text(errors="replace")
    assert done.returncode == 0, log[-3000:]
    if shutil.which("pdftoppm"):
        subprocess.run(["pdftoppm", "-png", "-r", "110", "page.pdf", "page"], cwd=tmp_path)
    return log


def test_the_column_layout_is_one_metric_per_suite_and_overall(runs: list[str]) -> None:
    text = _latex(runs, grouping="suites", layout="column")
    assert r"\begin{table}[t]" in text and "table*" not in text
    assert r"\begin{tabularx}{\columnwidth}" in text and "resizebox" not in text
    assert r"\footnotesize" in text  # 8 pt in a 10 pt article
    header = next(line for line in text.splitlines() if line.startswith("Model &"))
    assert [c.strip(" \\") for c in header.split("&")] == [
        "Model",
        "Overall",
        "BM",
        "OS",
        "SU",
        "LH",
    ]
    rows = [line for line in text.splitlines() if line.count("&") == 5 and "Model" not in line]
    assert len(rows) == 3  # one row per model: both instructions averaged
    assert any(row.startswith("tiny-llava-interleave &") for row in rows)  # a local path's name
    # The partial Overall is noted once for the table, not once per row.
    assert text.count("Partial Overall") == 1


def test_columns_picks_the_metrics(runs: list[str]) -> None:
    text = _latex(runs, grouping="paper", layout="column", columns=("Succ", "Loc"))
    top = next(line for line in text.splitlines() if r"\multicolumn{4}" in line)
    assert top.index("Succ") < top.index("Loc") and "Tot" not in top
    with pytest.raises(UnknownNameError, match="Bogus"):
        _latex(runs, layout="column", columns=("Bogus",))


def test_the_wide_layout_is_a_table_star_at_7pt(runs: list[str]) -> None:
    text = _latex(runs, grouping="suites", layout="wide")
    assert r"\begin{table*}[t]" in text and r"\begin{tabularx}{\textwidth}" in text
    assert r"\scriptsize" in text and "resizebox" not in text
    assert text.count("Partial Overall") == 1


needs_pdflatex = pytest.mark.skipif(
    shutil.which("pdflatex") is None, reason="pdflatex is not installed"
)


@needs_pdflatex
@pytest.mark.parametrize("layout", ["column", "wide"])
def test_compact_tables_compile_in_a_two_column_article_without_overfull_boxes(
    runs: list[str], tmp_path: Path, layout: str
) -> None:
    document = _latex(runs, layout=layout, standalone=True)
    assert document.startswith(r"\documentclass[twocolumn]{article}")
    log = _compile(tmp_path, document)
    assert "Overfull" not in log, re.findall(r"Overfull.*", log)
    assert (tmp_path / "page.pdf").stat().st_size > 0
