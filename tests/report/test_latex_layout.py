"""LaTeX ready to paste: standard spacing at natural size (``--fit-width`` scales), display
names for rows, execution columns only when some row was executed; both groupings compile
unscaled onto their page."""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from vlm_bench.errors import UnknownNameError
from vlm_bench.report import build_report, render_tables, report_options
from vlm_bench.report.names import parse_labels

if TYPE_CHECKING:
    from tests.conftest import Cli

TASKS = ("standard_pick_place", "target_color_yellow", "synonym_block_bin", "tower_stacking")


@pytest.fixture
def runs(
    tmp_path: Path, make_record: Callable[..., Any], make_run: Callable[..., Path]
) -> list[str]:
    """Two card models and one bare model string, planning only, every suite."""
    out = []
    for n, model in enumerate(("qwen2.5-vl-7b", "hf/some-org/Unknown-VLM", "llava-onevision-7b")):
        recs = [
            make_record(model, t, 0, v, 30.0 + 10 * n + i, run=f"run{n}")
            for i, t in enumerate(TASKS)
            for v in ("explicit", "implicit")
        ]
        out.append(str(make_run(Path(tmp_path) / f"run{n}", recs, execute=False)))
    return out


def _latex(runs: list[str], **options: Any) -> str:
    text = render_tables(build_report(report_options(runs=tuple(runs), format="latex", **options)))
    assert isinstance(text, str)
    return text


def test_natural_size_with_standard_spacing_unless_fit_width(runs: list[str]) -> None:
    text = _latex(runs)
    assert r"\resizebox" not in text and r"\tabcolsep" not in text and r"\footnotesize" in text
    fitted = _latex(runs, fit_width=True)
    assert fitted.count(r"\resizebox{\textwidth}{!}{%") == 2
    assert fitted.count(r"\end{tabular}}") == 2


def test_rows_carry_display_names(runs: list[str]) -> None:
    text = _latex(runs, grouping="paper")
    assert "Qwen2.5-VL-7B-Instruct" in text and "LLaVA-OneVision-Qwen2-7B-OV" in text
    assert "hf/some-org/Unknown-VLM" in text  # no card: the model string
    labelled = _latex(runs, grouping="paper", labels={"run2": "LLaVA-OV 7B", "run0": "Qwen 7B"})
    assert "LLaVA-OV 7B" in labelled and "Qwen 7B" in labelled
    assert "LLaVA-OneVision-Qwen2-7B-OV" not in labelled
    with pytest.raises(UnknownNameError, match="run1"):
        _latex(runs, labels={"nope": "X"})


def test_label_option_is_run_equals_name(cli: Cli, runs: list[str]) -> None:
    assert parse_labels(("run0=Qwen 7B",)) == {"run0": "Qwen 7B"}
    result = cli.result("report", *runs, "-f", "latex", "--label", "Qwen 7B")
    assert result.exit_code != 0 and "RUN=NAME" in str(result.exception)
    out = cli.invoke("report", *runs, "-f", "latex", "--label", "run0=Qwen 7B", "--fit-width")
    assert "Qwen 7B" in out and r"\resizebox" in out


def test_no_execution_columns_when_no_row_was_executed(runs: list[str]) -> None:
    text = _latex(runs)
    assert "Exec" not in text and "Task" not in text


def _compile(tex: Path) -> str:
    done = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name],
        cwd=tex.parent, capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-2000:]
    return done.stdout


def test_both_groupings_compile_unscaled_without_overfull_boxes(
    runs: list[str], tmp_path: Path
) -> None:
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed (apt-get install texlive-latex-recommended)")
    for grouping in ("paper", "suites"):
        tex = tmp_path / f"{grouping}.tex"
        tex.write_text(_latex(runs, grouping=grouping, standalone=True), encoding="utf-8")
        log = _compile(tex)
        assert "Overfull" not in log, grouping
        assert r"\resizebox" not in tex.read_text()
