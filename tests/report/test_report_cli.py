"""``vlm-bench report`` end to end on real oracle, random and mock runs; bad inputs."""

from __future__ import annotations

import importlib.util
import io
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import pytest

if TYPE_CHECKING:
    from tests.conftest import Cli


def _report(cli: Cli, *args: str) -> str:
    return cli.invoke("report", *args)


def _runs(real_runs: dict[str, Path]) -> list[str]:
    return [str(real_runs[m]) for m in ("oracle", "random", "mock")]


def test_terminal_table_in_both_groupings(cli: Cli, real_runs: dict[str, Path]) -> None:
    out = _report(cli, *_runs(real_runs), "--paired", "random", "--n-boot", "300")
    assert "Our four suites" in out and "The paper's three columns" in out
    assert "Overall with confidence intervals" in out and "Parse tiers" in out
    assert "Paired comparison with random" in out and "no_json" in out
    for model in ("oracle", "random", "mock"):
        assert model in out


def test_markdown_csv_and_by_columns(cli: Cli, real_runs: dict[str, Path], tmp_path: Path) -> None:
    md = _report(cli, *_runs(real_runs), "-f", "markdown", "--n-boot", "200")
    assert md.startswith("# vlm-bench report")
    assert "| oracle | both | 100.0 | 100.0 | 100.0 | 100.0 | 100.0 | 100.0 |" in md
    assert "BM = Base Manipulation, DI = Distractor Interference" in md
    csv = _report(cli, *_runs(real_runs), "-f", "csv", "--grouping", "paper", "--n-boot", "200")
    table = pd.read_csv(io.StringIO(csv))
    assert set(table.grouping) == {"paper"} and {"S_total_lo", "S_total_hi"} <= set(table.columns)
    oracle = table[(table.model == "oracle") & (table.group == "overall")]
    assert (oracle.S_total == 100.0).all() and (oracle.Succ == 100.0).all()
    mock = table[
        (table.model == "mock") & (table.group == "overall") & (table.instruction == "both")
    ]
    assert mock.iloc[0].n_error == 2  # the scripted timeouts
    by = _report(cli, *_runs(real_runs), "-f", "csv", "--by", "backend,resolution", "--no-stats")
    assert {"backend", "resolution"} <= set(pd.read_csv(io.StringIO(by)).columns)


def test_latex_parquet_episodes_and_sorting(
    cli: Cli, real_runs: dict[str, Path], tmp_path: Path
) -> None:
    tex = tmp_path / "table.tex"
    _report(cli, *_runs(real_runs), "-f", "latex", "--out", str(tex), "--sort", "total")
    text = tex.read_text()
    assert text.count(r"\begin{table*}") == 2 and r"\toprule" in text
    blocks = [
        line for line in text.split("tab:vlm_planning_paper")[1].splitlines() if "Exp." in line
    ]
    assert ["random" in blocks[0], "mock" in blocks[1], "oracle" in blocks[2]] == [True] * 3
    if importlib.util.find_spec("pyarrow") is None:
        pytest.skip("pyarrow is not installed (pip install 'vlm-bench[report]')")
    pq = tmp_path / "table.parquet"
    _report(cli, *_runs(real_runs), "-f", "parquet", "--out", str(pq), "--no-stats",
            "--episodes", str(tmp_path / "episodes.parquet"))  # fmt: skip
    assert set(pd.read_parquet(pq).grouping) == {"suites", "paper"}
    episodes = pd.read_parquet(tmp_path / "episodes.parquet")
    assert len(episodes) == 24 and set(episodes.run) == {"oracle", "random", "mock"}


def test_plots_are_written(cli: Cli, real_runs: dict[str, Path], tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    from PIL import Image

    _report(
        cli, *_runs(real_runs), "--plots", str(tmp_path / "plots"), "--no-stats", "--n-boot", "200"
    )
    for name in ("metrics.png", "radar.png", "loc_by_direction.png"):
        with Image.open(tmp_path / "plots" / name) as image:
            assert image.width > 500 and len(image.getcolors(100_000) or []) > 20


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["/no/such/run"], "run folder '/no/such/run' does not exist"),
        (["{oracle}", "--by", "modle"], "unknown --by column 'modle'; valid:"),
        (["{oracle}", "--format", "html"], "invalid report option format: Input should be"),
        (["{oracle}", "--by", "run", "--paired", "gpt"], "unknown run 'gpt'; valid: oracle"),
        (["{oracle}", "-f", "parquet"], "give --out FILE"),
        (["{oracle}", "-f", "markdown", "--out", "/no/such/dir/t.md"], "does not exist"),
    ],
)
def test_bad_inputs_are_one_line_errors(
    cli: Cli, real_runs: dict[str, Path], args: list[str], message: str
) -> None:
    done = cli.run("report", *(a.format(oracle=real_runs["oracle"]) for a in args))
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], lines
    assert "Traceback" not in done.stderr


def test_nothing_is_written_before_every_check_passed(
    cli: Cli, real_runs: dict[str, Path], tmp_path: Path
) -> None:
    outputs = [
        "--out",
        str(tmp_path / "t.md"),
        "--plots",
        str(tmp_path / "plots"),
        "--gallery",
        str(tmp_path / "gallery"),
        "--episodes",
        str(tmp_path / "e.csv"),
    ]
    result = cli.result("report", str(real_runs["oracle"]), "-f", "markdown", "--by", "nope",
                          *outputs)  # fmt: skip
    assert result.exit_code != 0 and "nope" in str(result.exception)
    assert list(tmp_path.iterdir()) == []


def test_the_report_command_gives_the_gallery_its_views(
    cli: Cli, real_runs: dict[str, Path], tmp_path: Path
) -> None:
    gallery = tmp_path / "gallery"
    result = cli.result("report", str(real_runs["mock"]), "--gallery", str(gallery), "--no-render")
    assert result.exit_code == 0, result.output
    assert len(list(gallery.rglob("img/*.jpg"))) == 4 * 4  # from the runs' snapshot cache


def test_the_report_command_defaults_are_the_report_options_defaults() -> None:
    import inspect

    from vlm_bench.cli.report_cmd import report
    from vlm_bench.report.report_options import ReportOptions

    params = inspect.signature(report).parameters
    for name in ("n_boot", "seed", "mixed_versions", "inline_images"):
        assert params[name].default == ReportOptions.model_fields[name].default, name
