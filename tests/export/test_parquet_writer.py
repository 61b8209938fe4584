"""The shard writer holds at most one row group of rows, and numbers shards as the Hub does."""

from __future__ import annotations

import io
from pathlib import Path

import datasets
import pyarrow.parquet as pq
from PIL import Image

from vlm_bench.export.features import dataset_features, row_record
from vlm_bench.export.parquet_writer import ROW_GROUP_ROWS, ShardWriter, shard_names
from vlm_bench.export.row_model import DatasetRow, GtStep


def _row(i: int) -> DatasetRow:
    png = io.BytesIO()
    Image.new("RGB", (4, 4), (i, 0, 0)).save(png, format="PNG")
    return DatasetRow(
        key=f"t/{i}/explicit",
        benchmark_version=1,
        task_id="t",
        suite="long_horizon",
        seed=i,
        instruction="explicit",
        instruction_text="do it",
        system="s",
        user="<image:uav>\ndo it",
        views=("uav",),
        images={"uav": png.getvalue()},
        objects=("a",),
        gt_plan='[{"subtask": 0, "tasktype": "ARM", "object": "a", "skill": "pick"}]',
        gt_steps=(GtStep(subtask=0, tasktype="ARM", object="a", skill="pick"),),
        prompt_hash="h",
        example_ids=(),
    )


def test_rows_are_written_a_row_group_at_a_time(tmp_path: Path) -> None:
    names = shard_names("test", 25, 20)
    assert names == ["test-00000-of-00002.parquet", "test-00001-of-00002.parquet"]
    writer = ShardWriter(tmp_path, dataset_features(["uav"]), names, 20)
    held = []
    for i in range(25):
        writer.add(row_record(_row(i)))
        held.append(len(writer._group))
    paths = writer.close()
    assert max(held) < ROW_GROUP_ROWS  # a full group is written at once
    groups = [
        [
            pq.ParquetFile(p).metadata.row_group(g).num_rows
            for g in range(pq.ParquetFile(p).num_row_groups)
        ]
        for p in paths
    ]
    assert groups == [[10, 10], [5]]
    ds = datasets.load_dataset("parquet", data_files=[str(p) for p in paths], split="train")
    assert ds["seed"] == list(range(25))
    assert ds[3]["image_uav"].getpixel((0, 0)) == (3, 0, 0)
    assert ds[0]["gt_steps"][0]["skill"] == "pick" and ds[0]["gt_steps"][0]["target"] is None


def test_no_rows_still_make_one_shard(tmp_path: Path) -> None:
    names = shard_names("test", 0, 100)
    assert names == ["test-00000-of-00001.parquet"]
    writer = ShardWriter(tmp_path, dataset_features(["uav"]), names, 100)
    (path,) = writer.close()
    assert pq.ParquetFile(path).metadata.num_rows == 0
