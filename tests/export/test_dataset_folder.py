"""``vlm-bench export dataset``: a folder ``datasets.load_dataset`` reads as is, written
streamed and deterministically, and refused where it would overwrite or is asked wrongly."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import datasets
import pyarrow.parquet as pq
import pytest

from vlm_bench.export.card import read_card_options
from vlm_bench.export.dataset_export import DatasetExport
from vlm_bench.export.parquet_writer import ROW_GROUP_ROWS
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION

from .conftest import SMALL

if TYPE_CHECKING:
    from tests.conftest import Cli


def test_load_dataset_reads_the_folder_with_its_features(small: DatasetExport) -> None:
    ds = datasets.load_dataset(str(small.folder))
    assert list(ds) == ["test"]
    test = ds["test"]
    assert test.num_rows == small.rows == 4
    assert [r["key"] for r in test] == [
        "standard_pick_place/0/explicit",
        "standard_pick_place/0/implicit",
        "drawer_interaction/0/explicit",
        "drawer_interaction/0/implicit",
    ]
    for view in ("uav", "wrist", "overhead", "side"):
        assert isinstance(test.features[f"image_{view}"], datasets.Image)
    row = test[0]
    assert row["image_uav"].size == (64, 64)
    assert row["benchmark_version"] == BENCHMARK_VERSION
    assert row["suite"] == "base_manipulation" and test[2]["suite"] == "long_horizon"
    assert row["views"] == ["uav", "wrist", "overhead", "side"]
    assert json.loads(row["gt_plan"]) == [
        {k: v for k, v in step.items() if v is not None} for step in row["gt_steps"]
    ]
    assert row["user"].count("<image:") == 4 and row["instruction_text"] in row["user"]


def test_shards_are_hub_named_and_hold_row_groups(small: DatasetExport) -> None:
    names = sorted(p.name for p in (small.folder / "data").iterdir())
    assert names == ["test-00000-of-00002.parquet", "test-00001-of-00002.parquet"]
    assert [pq.ParquetFile(p).metadata.num_rows for p in small.shards] == [3, 1]
    assert small.bytes == sum(p.stat().st_size for p in small.folder.rglob("*") if p.is_file())
    assert ROW_GROUP_ROWS >= 3  # the shards above are one row group each


def test_the_card_records_version_options_and_split(small: DatasetExport) -> None:
    text = (small.folder / "README.md").read_text()
    section = read_card_options(text)
    assert section["benchmark_version"] == BENCHMARK_VERSION
    assert section["rows"] == 4
    options = section["options"]
    assert options["tasks"] == list(SMALL["tasks"]) and options["seeds"] == [0]
    assert options["resolution"] == 64 and options["instructions"] == ["explicit", "implicit"]
    assert "license: apache-2.0" in text
    card = datasets.load_dataset_builder(str(small.folder)).info
    assert card.splits["test"].num_examples == 4


def test_the_same_export_twice_is_the_same_bytes(
    small: DatasetExport, exporter: Callable[..., DatasetExport]
) -> None:
    again = exporter("small-again", **SMALL)
    files = sorted(p.relative_to(small.folder) for p in small.folder.rglob("*") if p.is_file())
    assert files == sorted(
        p.relative_to(again.folder) for p in again.folder.rglob("*") if p.is_file()
    )
    for name in files:
        assert (small.folder / name).read_bytes() == (again.folder / name).read_bytes(), name


def test_prompt_options_shape_the_columns(exporter: Callable[..., DatasetExport]) -> None:
    made = exporter(
        "text",
        tasks=("drawer_interaction",),
        seeds=(1,),
        instructions=("implicit",),
        views=("overhead", "uav"),
        resolution=32,
        k_shot=0,
        object_list=False,
        scene_as_text=True,
    )
    row = datasets.load_dataset(str(made.folder), split="test")[0]
    assert row["views"] == ["overhead", "uav"] and "image_wrist" not in row
    assert row["user"].index("<image:overhead>") < row["user"].index("<image:uav>")
    assert row["example_ids"] == [] and "Scene:" in row["user"]
    assert "Objects in the scene" not in row["user"]
    assert row["image_overhead"].size == (32, 32)


def test_a_non_empty_folder_is_refused_without_force(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "ds"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    args = ["export", "dataset", str(out), "--task", "drawer_interaction", "--seeds", "0"]
    done = cli.run(*args, "--resolution", "32", "--no-progress")
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"error: {out} is not empty; pass --force to replace the dataset in it"
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ds"]
    assert [p.name for p in out.iterdir()] == ["notes.txt"]


def test_force_replaces_an_earlier_export(
    cli: Cli, tmp_path: Path, small: DatasetExport, snapshot_cache: Path
) -> None:
    import shutil

    out = tmp_path / "ds"
    shutil.copytree(small.folder, out)
    args = ["export", "dataset", str(out), "--task", "drawer_interaction", "--seeds", "0"]
    args += ["--instruction", "implicit", "--resolution", "64", "--no-progress", "--force"]
    done = cli.run(*args, env={**_env(), "VLM_BENCH_SNAPSHOT_CACHE": str(snapshot_cache)})
    assert done.returncode == 0, done.stderr
    assert "1 rows in 1 Parquet file(s)" in done.stdout
    assert [p.name for p in (out / "data").iterdir()] == ["test-00000-of-00001.parquet"]
    assert datasets.load_dataset(str(out), split="test")["key"] == ["drawer_interaction/0/implicit"]
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [
        ("--views", "uav,top", "unknown camera view 'top'"),
        ("--task", "no_such_task", "unknown task 'no_such_task'"),
        ("--resolution", "8", "invalid export option resolution"),
        ("--k-shot", "-1", "invalid export option k_shot"),
        ("--seeds", "3-1", "empty seed range '3-1'"),
        ("--instruction", "vague", "unknown instruction variant 'vague'"),
        ("--suite", "hard", "unknown suite 'hard'"),
    ],
)
def test_bad_options_are_one_line_and_write_nothing(
    cli: Cli, tmp_path: Path, option: str, value: str, message: str
) -> None:
    out = tmp_path / "ds"
    done = cli.run("export", "dataset", str(out), option, value, "--no-progress")
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], lines
    assert list(tmp_path.iterdir()) == []


def test_a_missing_extra_names_it(cli: Cli, tmp_path: Path) -> None:
    code = "import sys; sys.modules['datasets'] = None; from vlm_bench.cli.main import main; main()"
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-c", code, "export", "dataset", str(tmp_path / "ds"), "--no-progress"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert done.stderr.strip() == (
        "error: datasets is not installed; install it with: pip install 'vlm-bench[dataset]'"
    )
    assert list(tmp_path.iterdir()) == []


def _env() -> dict[str, str]:
    import os

    return dict(os.environ)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--no-images"], "No such option: --no-images"),
        (["--shard-rows", "0"], "--shard-rows must be at least 1, got 0"),
    ],
)
def test_unknown_options_and_bad_shards_are_one_line(
    cli: Cli, tmp_path: Path, args: list[str], message: str
) -> None:
    done = cli.run("export", "dataset", str(tmp_path / "ds"), *args, "--no-progress")
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], lines
    assert list(tmp_path.iterdir()) == []
