"""The writer's folder against LeRobotDataset v3.0's published layout (lerobot's
``datasets/utils.py`` constants and ``get_hf_features_from_features``): the files, info.json,
the Parquet schemas, the tasks table, the statistics, and the frames of each video."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from tests.demos.conftest import FPS, LENGTHS, SIZE, TASKS, VIEWS, write_synthetic
from vlm_bench.vla.demos.lerobot_writer import EpisodeData
from vlm_bench.vla.demos.reader import DemoDataset

Synthetic = tuple[Path, list[EpisodeData]]


def test_the_folder_holds_the_v3_files(synthetic: Synthetic) -> None:
    root, _ = synthetic
    files = sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())
    assert files == sorted(
        [
            "data/chunk-000/file-000.parquet",
            "meta/episodes/chunk-000/file-000.parquet",
            "meta/info.json",
            "meta/stats.json",
            "meta/tasks.parquet",
            *(f"videos/observation.images.{v}/chunk-000/file-000.mp4" for v in VIEWS),
        ]
    )


def test_info_json_counts_and_features(synthetic: Synthetic) -> None:
    root, _ = synthetic
    info = json.loads((root / "meta/info.json").read_text())
    assert info["codebase_version"] == "v3.0" and info["fps"] == FPS
    assert info["total_episodes"] == 3 and info["total_frames"] == sum(LENGTHS)
    assert info["total_tasks"] == len(set(TASKS)) and info["splits"] == {"train": "0:3"}
    assert info["data_path"] == "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    assert info["video_path"] == (
        "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
    )
    feats = info["features"]
    assert feats["observation.state"]["shape"] == [15] and feats["action"]["shape"] == [12]
    assert feats["action"]["names"][:4] == ["dx", "dy", "dz", "dyaw"]
    assert feats["action"]["names"][-1] == "gripper"
    for view in VIEWS:
        video = feats[f"observation.images.{view}"]
        assert video["dtype"] == "video" and video["shape"] == [SIZE, SIZE, 3]
        assert video["names"] == ["height", "width", "channels"]
        assert video["info"]["video.fps"] == FPS and video["info"]["video.codec"] == "h264"
    for name in ("frame_index", "episode_index", "index", "task_index"):
        assert feats[name] == {"dtype": "int64", "shape": [1], "names": None}
    assert feats["timestamp"] == {"dtype": "float32", "shape": [1], "names": None}


def test_the_frame_table_has_lerobots_arrow_types(synthetic: Synthetic) -> None:
    root, episodes = synthetic
    table = pq.read_table(root / "data/chunk-000/file-000.parquet")
    schema = table.schema
    assert schema.field("observation.state").type == pa.list_(pa.float32(), 15)
    assert schema.field("action").type == pa.list_(pa.float32(), 12)
    assert schema.field("timestamp").type == pa.float32()
    for name in ("frame_index", "episode_index", "index", "task_index"):
        assert schema.field(name).type == pa.int64()
    assert table.column("index").to_pylist() == list(range(sum(LENGTHS)))
    frame = table.column("frame_index").to_pylist()
    assert frame[: LENGTHS[0]] == list(range(LENGTHS[0])) and frame[LENGTHS[0]] == 0
    stamps = np.array(table.column("timestamp").to_pylist()[: LENGTHS[0]])
    assert np.allclose(stamps, np.arange(LENGTHS[0]) / FPS)
    got = np.array(table.column("action").to_pylist()[: LENGTHS[0]], dtype=np.float32)
    assert np.array_equal(got, episodes[0].actions)


def test_episodes_and_tasks_tables_locate_every_episode(synthetic: Synthetic) -> None:
    root, _ = synthetic
    rows = pq.read_table(root / "meta/episodes/chunk-000/file-000.parquet").to_pylist()
    assert [r["length"] for r in rows] == list(LENGTHS)
    assert [r["tasks"] for r in rows] == [[t] for t in TASKS]
    starts = np.cumsum([0, *LENGTHS])
    assert [r["dataset_from_index"] for r in rows] == starts[:-1].tolist()
    assert [r["dataset_to_index"] for r in rows] == starts[1:].tolist()
    for view in VIEWS:
        key = f"videos/observation.images.{view}"
        assert [r[f"{key}/from_timestamp"] for r in rows] == (starts[:-1] / FPS).tolist()
        assert [r[f"{key}/to_timestamp"] for r in rows] == (starts[1:] / FPS).tolist()
    tasks = pd.read_parquet(root / "meta/tasks.parquet")
    assert tasks.index.name == "task"
    assert tasks.loc["Push the box.", "task_index"] == 1


def test_stats_cover_state_action_and_images(synthetic: Synthetic) -> None:
    root, episodes = synthetic
    stats = json.loads((root / "meta/stats.json").read_text())
    actions = np.concatenate([e.actions for e in episodes])
    assert np.allclose(stats["action"]["mean"], actions.mean(0), atol=1e-6)
    assert np.allclose(stats["action"]["std"], actions.std(0), atol=1e-6)
    assert stats["action"]["count"] == [sum(LENGTHS)]
    image = stats["observation.images.wrist"]
    assert np.array(image["mean"]).shape == (3, 1, 1)
    assert 0.0 <= np.array(image["min"]).min() <= np.array(image["max"]).max() <= 1.0


def test_the_reader_gets_the_arrays_and_the_video_frames_back(synthetic: Synthetic) -> None:
    root, episodes = synthetic
    dataset = DemoDataset(root)
    assert len(dataset) == 3 and dataset.views == list(VIEWS)
    for k, written in enumerate(episodes):
        stored = dataset.episode(k)
        assert stored.task == written.task
        assert np.array_equal(stored.states, written.states)
        assert np.array_equal(stored.actions, written.actions)
        frames = dataset.images(k, "overhead")
        assert frames.shape == written.images["overhead"].shape
        error = np.abs(frames.astype(int) - written.images["overhead"].astype(int)).mean()
        assert error < 6  # lossy H.264, but each episode's own frames (not a neighbour's)


def test_the_same_episodes_write_the_same_bytes(tmp_path: Path) -> None:
    first, second = tmp_path / "a", tmp_path / "b"
    write_synthetic(first)
    write_synthetic(second)
    files = sorted(p.relative_to(first) for p in first.rglob("*") if p.is_file())
    assert len(files) == 7
    for rel in files:
        assert (first / rel).read_bytes() == (second / rel).read_bytes(), rel
