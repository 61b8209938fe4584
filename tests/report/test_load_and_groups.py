"""``load(*runs)``: tidy rows with the manifest's settings; the paper's column mapping."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.errors import ConfigError, DataFileError, UnknownNameError
from vlm_bench.report import (
    DERIVED,
    SETTINGS,
    grouping,
    load,
    paper_grouping,
    records_frame,
    summary_long,
)
from vlm_bench.report.groups import PAPER_COLUMNS_FILE, paper_columns

RUN_V1 = Path(__file__).parents[1] / "storage" / "data" / "run_v1"


def test_load_adds_settings_and_derived_columns(
    tmp_path: Path, make_record: Callable[..., Any], make_run: Callable[..., Path]
) -> None:
    a = make_run(tmp_path / "a", [make_record("m", "standard_pick_place", 0, "explicit", 50.0)],
                 views=("uav", "overhead"), resolution=224)  # fmt: skip
    b = make_run(tmp_path / "b", [make_record("m", "tower_stacking", 1, "implicit", 10.0)])
    frame = load(a, b)
    assert len(frame) == 2 and list(frame.run) == ["a", "b"]
    assert set(SETTINGS) | set(DERIVED) <= set(frame.columns)
    first = frame.iloc[0]
    assert (first.views, first.n_views, first.resolution) == ("uav,overhead", 2, 224)
    assert (first.first_move, first.gt_steps, first.paper_column) == (
        "front",
        3,
        "base_manipulation",
    )
    assert frame.iloc[1].views == "uav,wrist,overhead,side"
    assert frame.iloc[1].paper_column == "long_horizon"
    # ``--by`` any of them: an ablation table by views.
    long = summary_long(frame, ["model", "views"])
    assert set(long.views) == {"uav,overhead", "uav,wrist,overhead,side"}


def test_load_expands_globs_and_skips_files(
    tmp_path: Path, make_record: Callable[..., Any], make_run: Callable[..., Path]
) -> None:
    rec = make_record("m", "standard_pick_place", 0, "explicit", 50.0)
    for name in ("r1", "r2"):
        make_run(tmp_path / "x" / name, [rec])
    (tmp_path / "x" / "README.md").write_text("not a run")
    (tmp_path / "x" / "empty").mkdir()
    assert list(load(tmp_path / "x" / "r*").run) == ["r1", "r2"]
    assert list(load(str(tmp_path / "x" / "*")).run) == ["r1", "r2"]  # no manifest: skipped
    assert len(load(tmp_path / "x" / "r1", tmp_path / "x" / "README.md")) == 1  # shell glob


def test_same_folder_names_get_their_parents(
    tmp_path: Path, make_record: Callable[..., Any], make_run: Callable[..., Path]
) -> None:
    rec = make_record("m", "standard_pick_place", 0, "explicit", 50.0)
    a, b = make_run(tmp_path / "one" / "run", [rec]), make_run(tmp_path / "two" / "run", [rec])
    assert list(load(a, b).run) == ["one/run", "two/run"]


@pytest.mark.parametrize(
    ("path", "message"),
    [("missing", "does not exist"), ("empty", "no manifest.json"), ("nothing*", "no run folder")],
)
def test_load_errors_are_one_line(tmp_path: Path, path: str, message: str) -> None:
    (tmp_path / "empty").mkdir()
    with pytest.raises(ConfigError, match=message) as info:
        load(tmp_path / path)
    assert "\n" not in str(info.value)


def test_first_release_runs_still_load() -> None:
    frame = load(RUN_V1)
    assert len(frame) == 4 and set(frame.status) == {"ok", "error"}
    assert frame.iloc[0].backend == "mock" and not frame.iloc[0].execute


def test_paper_columns_cover_every_task_once() -> None:
    columns = paper_columns()
    assert [c.title for c in columns.columns] == [
        "Base Manipulation", "Distractor Interference", "Long-Horizon"]  # fmt: skip
    mapping = columns.column_of()
    assert set(mapping) == {t.id for t in all_tasks()}
    for task in all_tasks():  # our documented choice: OS and SU form Distractor Interference
        expected = {"base_manipulation": "base_manipulation", "long_horizon": "long_horizon"}
        assert mapping[task.id] == expected.get(task.suite.value, "distractor_interference")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["columns"][0]["tasks"].append("tower_stacking"), "more than one column"),
        (lambda d: d["columns"][0]["tasks"].append("no_such_task"), "unknown task 'no_such_task'"),
        (lambda d: d["columns"][2]["tasks"].remove("tower_stacking"), "'tower_stacking' is in no"),
        (lambda d: d["columns"][0].pop("title"), r"columns\[0\].title: Field required"),
    ],
)
def test_bad_paper_column_files_name_the_problem(
    tmp_path: Path, edit: Callable[[dict[str, Any]], object], message: str
) -> None:
    data = json.loads(PAPER_COLUMNS_FILE.read_text())
    edit(data)
    path = tmp_path / "columns.json"
    path.write_text(json.dumps(data))
    with pytest.raises(DataFileError, match=message):
        paper_columns(path)


def test_paper_grouping_pools_object_spatial_and_semantic(make_record: Callable[..., Any]) -> None:
    recs = [
        make_record("m", "standard_pick_place", 0, "explicit", 100.0),
        make_record("m", "target_color_yellow", 0, "explicit", 40.0),
        make_record("m", "target_color_yellow", 1, "explicit", 20.0),
        make_record("m", "synonym_block_bin", 0, "explicit", 90.0),
        make_record("m", "tower_stacking", 0, "explicit", 30.0),
    ]
    long = summary_long(records_frame(recs), grouping=paper_grouping())
    cells = long.set_index("paper_column").S_total
    assert cells["distractor_interference"] == pytest.approx(50.0)  # (40 + 20 + 90) / 3
    assert cells["overall"] == pytest.approx((100 + 50 + 30) / 3)
    suites = summary_long(records_frame(recs)).set_index("suite").S_total
    assert suites["overall"] == pytest.approx((100 + 30 + 90 + 30) / 4)


def test_unknown_grouping_and_custom_tasks() -> None:
    with pytest.raises(UnknownNameError, match="valid: paper, suites"):
        grouping("columns")
    frame = records_frame([])
    assert summary_long(frame, grouping=paper_grouping()).empty
