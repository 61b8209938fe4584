"""Golden Markdown and LaTeX of a small fixed set of records; the LaTeX compiles with pdflatex.

Regenerate after a reviewed change with ``VLM_BENCH_UPDATE_GOLDEN=1 pytest tests/report``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from vlm_bench.report import build_report, render_tables, report_options
from vlm_bench.report.latex import latex_document

GOLDEN = Path(__file__).parent / "golden"
UPDATE = os.environ.get("VLM_BENCH_UPDATE_GOLDEN") == "1"


@pytest.fixture
def runs(
    tmp_path: Path,
    make_record: Callable[..., Any],
    make_execution: Callable[..., Any],
    make_run: Callable[..., Path],
) -> list[Path]:
    """Two models over 5 tasks (4 suites, 3 paper columns), both instructions; ``beta`` executes
    its plans and one of its episodes failed in the backend."""
    r, ok, fail = make_record, make_execution(True, 100.0), make_execution(False, 50.0)
    alpha = [
        r("alpha", "standard_pick_place", 0, "explicit", 100.0, succ=True),
        r("alpha", "standard_pick_place", 0, "implicit", 75.0, loc=0.0),
        r("alpha", "color_distractor_green", 0, "explicit", 50.0),
        r("alpha", "color_distractor_green", 0, "implicit", 62.5),
        r("alpha", "target_color_yellow", 0, "explicit", 40.0),
        r("alpha", "target_color_yellow", 0, "implicit", 20.0),
        r("alpha", "synonym_block_bin", 0, "explicit", 80.0, loc=40.0),
        r("alpha", "synonym_block_bin", 0, "implicit", 90.0),
        r("alpha", "tower_stacking", 0, "explicit", 30.0),
        r("alpha", "tower_stacking", 0, "implicit", 0.0, tier="invalid"),
    ]
    beta = [
        r("beta", "standard_pick_place", 0, "explicit", 100.0, succ=True, executed=ok),
        r("beta", "standard_pick_place", 0, "implicit", 100.0, succ=True, executed=ok),
        r("beta", "color_distractor_green", 0, "explicit", 87.5, executed=fail),
        r("beta", "color_distractor_green", 0, "implicit", None),
        r("beta", "target_color_yellow", 0, "explicit", 70.0, executed=fail),
        r("beta", "target_color_yellow", 0, "implicit", 65.0, executed=fail),
        r("beta", "synonym_block_bin", 0, "explicit", 95.0, executed=ok),
        r("beta", "synonym_block_bin", 0, "implicit", 95.0, executed=ok),
        r("beta", "tower_stacking", 0, "explicit", 55.0, executed=fail),
        r("beta", "tower_stacking", 0, "implicit", 0.0, tier="invalid"),
    ]
    return [
        make_run(tmp_path / "alpha", alpha, execute=False),
        make_run(tmp_path / "beta", beta, execute=True),
    ]


def _check(name: str, text: str) -> None:
    path = GOLDEN / name
    if UPDATE:
        GOLDEN.mkdir(exist_ok=True)
        path.write_text(text, encoding="utf-8")
    assert path.is_file(), f"missing golden {path}; run with VLM_BENCH_UPDATE_GOLDEN=1"
    expected = path.read_text(encoding="utf-8")
    assert text == expected, f"{name} changed; review, then VLM_BENCH_UPDATE_GOLDEN=1 to accept"


def _tables(runs: list[Path], fmt: str, **options: Any) -> str:
    opts = report_options(runs=tuple(map(str, runs)), format=fmt, stats=False, **options)
    text = render_tables(build_report(opts))
    assert isinstance(text, str)
    return text


def test_markdown_golden(runs: list[Path]) -> None:
    _check("tables.md", _tables(runs, "markdown"))


def test_latex_golden(runs: list[Path]) -> None:
    _check("tables.tex", _tables(runs, "latex", sort="total"))


def test_latex_marks_the_best_value_per_column(runs: list[Path]) -> None:
    text = _tables(runs, "latex", grouping="paper")
    rows = [line.split(" & ") for line in text.splitlines() if " & Exp. & " in line or
            line.startswith(" & Imp. & ")]  # fmt: skip
    assert len(rows) == 4  # alpha Exp., alpha Imp., beta Exp., beta Imp.
    # Base manipulation Plan: beta's implicit 100.0 is the column's best, in bold alone.
    assert [r[2] for r in rows] == ["75.0", "68.8", "93.8", r"\textbf{100.0}"]
    # Overall Tot spans each model's two rows (the ``both`` value): beta's 68.5 is bold.
    tot = 2 + 8 * 3 + 4  # label, instruction, 3 groups of 8 metrics, then Plan..Tot
    assert rows[0][tot].endswith("{45.7}") and "textbf" not in rows[0][tot]
    assert rows[2][tot].endswith(r"{\textbf{68.5}}") and rows[1][tot] == rows[3][tot] == ""
    assert "multirow" not in latex_document(text)


def test_latex_compiles_with_pdflatex(runs: list[Path], tmp_path: Path) -> None:
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed (apt-get install texlive-latex-recommended)")
    tex = tmp_path / "tables.tex"
    tex.write_text(_tables(runs, "latex", standalone=True), encoding="utf-8")
    done = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name],
        cwd=tmp_path, capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-2000:]
    assert (tmp_path / "tables.pdf").stat().st_size > 1000
    assert "Overfull" not in done.stdout or "resizebox" in tex.read_text()
