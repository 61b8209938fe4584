"""Narrowing a report (--suite, --task, --common), --label in every table, plot and gallery,
local model paths by their last component, partial bars marked, readable sector labels, the
gallery index in task/seed order, and piped listings that never cut an id."""

from __future__ import annotations

import io
import itertools
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import pytest

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.report import build_report, render_tables, report_options
from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS
from vlm_bench.types.records import EpisodeRecord

TASKS = ("standard_pick_place", "target_color_yellow", "synonym_block_bin", "tower_stacking")
if TYPE_CHECKING:
    from tests.conftest import Cli

LOCAL = "openai//srv/models/tiny-llava"


@pytest.fixture
def runs(
    tmp_path: Path, make_record: Callable[..., EpisodeRecord], make_run: Callable[..., Path]
) -> list[str]:
    """A full run of every suite and a run of the base suite only (seed 1 first)."""
    full = [
        make_record("oracle", t, s, v, 90.0)
        for t in TASKS
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]
    base = [
        make_record(LOCAL, TASKS[0], s, v, 30.0, run="rules-9eebacd6")
        for s in (1, 0)
        for v in ("explicit", "implicit")
    ]
    return [
        str(make_run(tmp_path / "oracle-1a2b", full)),
        str(make_run(tmp_path / "rules-9eebacd6", base)),
    ]


def _csv(runs: list[str], **options: object) -> pd.DataFrame:
    report = build_report(report_options(runs=tuple(runs), format="csv", stats=False, **options))
    return pd.read_csv(io.StringIO(str(render_tables(report))))


def _markdown(runs: list[str], **options: object) -> str:
    report = build_report(
        report_options(runs=tuple(runs), format="markdown", stats=False, **options)
    )
    return str(render_tables(report))


def test_suite_and_task_narrow_the_episodes(runs: list[str]) -> None:
    table = _csv(runs, grouping="suites", suites=("long_horizon",))
    assert set(table["group"]) == {"long_horizon", "overall"}
    table = _csv(runs, grouping="suites", tasks=(TASKS[1],))
    assert set(table["group"]) == {"object_spatial", "overall"}
    with pytest.raises(UnknownNameError, match="bogus_task"):
        _csv(runs, tasks=("bogus_task",))
    with pytest.raises(ConfigError, match="no episode"):
        _csv(runs[1:], suites=("long_horizon",))


def test_common_keeps_only_the_episodes_every_run_has(runs: list[str]) -> None:
    assert "Partial Overall" in _markdown(runs, grouping="suites")
    text = _markdown(runs, grouping="suites", common=True)
    assert "Partial Overall" not in text and "†" not in text
    table = _csv(runs, grouping="suites", common=True)
    assert set(table["group"]) == {"base_manipulation", "overall"}
    overall = table[(table["group"] == "overall") & (table["instruction"] != "both")]
    assert set(overall["n"]) == {2}  # 2 seeds per instruction


def test_labels_and_local_paths_name_the_rows_of_every_format(runs: list[str]) -> None:
    text = _markdown(runs, labels={"oracle-1a2b": "Oracle (GT)"})
    assert "| Oracle (GT) |" in text and "| oracle |" not in text
    assert "| tiny-llava |" in text and "/srv/models" not in text
    table = _csv(runs, labels={"rules-9eebacd6": "Rules"})
    assert set(table["model"]) == {"oracle", "Rules"}


def test_labels_name_the_galleries_and_the_runs(runs: list[str], tmp_path: Path) -> None:
    from vlm_bench.report.gallery_index import write_galleries

    options = report_options(
        runs=tuple(runs), stats=False, labels={"rules-9eebacd6": "Rules"}, by=("run",)
    )
    report = build_report(options)
    assert set(report.frame["run"]) == {"oracle-1a2b", "Rules"}
    written = write_galleries(report.frame, tmp_path / "gallery", options)
    assert (tmp_path / "gallery" / "Rules" / "index.html") in written
    index = (tmp_path / "gallery" / "index.html").read_text()
    assert "Rules" in index
    # Episodes by task, then seed (the base run wrote seed 1 first).
    order = [
        index.index(f"{TASKS[0]}_{seed}_{variant}.html")
        for seed in (0, 1)
        for variant in ("explicit", "implicit")
    ]
    assert order == sorted(order)
    tasks = [index.index(f"{t}_0_explicit.html") for t in sorted(TASKS)]
    assert tasks == sorted(tasks)


def test_partial_bars_are_marked(runs: list[str]) -> None:
    pytest.importorskip("matplotlib")
    from vlm_bench.report.plots import _partial

    report = build_report(report_options(runs=tuple(runs), n_boot=100, stats=False))
    assert _partial(report) == {("tiny-llava",): "OS, SU, LH"}


def _sector_runs(
    tmp_path: Path, make_record: Callable[..., EpisodeRecord], make_run: Callable[..., Path]
) -> list[str]:
    """Every sector, with three-digit episode counts (the widest labels)."""
    records = []
    for d, direction in enumerate(HORIZONTAL_DIRECTIONS):
        for seed in range(120):
            record = make_record("oracle", TASKS[seed % 4], d * 1000 + seed, "explicit", 50.0)
            data = record.model_dump(mode="json")
            data["gt_plan"][0]["direction"] = direction.value
            records.append(EpisodeRecord.model_validate(data))
    return [str(make_run(tmp_path / "sectors", records))]


def test_sector_labels_do_not_overlap(
    tmp_path: Path, make_record: Callable[..., EpisodeRecord], make_run: Callable[..., Path]
) -> None:
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from vlm_bench.report.plots import loc_by_direction_figure

    runs = _sector_runs(tmp_path, make_record, make_run)
    report = build_report(report_options(runs=tuple(runs), n_boot=100, stats=False))
    fig = loc_by_direction_figure(report)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
        labels = [t for t in fig.axes[0].get_xticklabels() if t.get_text()]
        assert len(labels) == len(HORIZONTAL_DIRECTIONS)
        boxes = [t.get_window_extent(renderer) for t in labels]
        for left, right in itertools.pairwise(boxes):
            assert left.x1 < right.x0, (left, right)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("command", ["models", "tasks"])
def test_piped_listings_never_cut_an_id(command: str) -> None:
    done = subprocess.run(
        [sys.executable, "-c", "from vlm_bench.cli.main import main; main()", command],
        capture_output=True,
        text=True,
        timeout=60,
        env={"COLUMNS": "80", "PATH": "/usr/bin:/bin"},
    )
    assert done.returncode == 0, done.stderr
    want = "glm-4.1v-9b-thinking" if command == "models" else "deformable_object_banana"
    assert want in done.stdout


def test_the_cli_passes_the_new_options(runs: list[str], cli: Cli) -> None:
    args = ["report", *runs, "-f", "latex", "--layout", "column", "--columns", "Tot,Succ"]
    text = cli.invoke(*args, "--suite", "bm", "--common", "--label", "oracle-1a2b=Oracle")
    assert r"\begin{tabularx}{\columnwidth}" in text and "Oracle &" in text
    assert "tiny-llava &" in text and "OS" not in text.split(r"\midrule")[0]
    bad = cli.result("report", *runs, "--layout", "column")  # a LaTeX option without LaTeX
    assert bad.exit_code != 0
