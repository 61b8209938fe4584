"""The LeRobotDataset v3.0 layout, as lerobot (0.4) reads it: paths, features, statistics.

::

    meta/info.json                                 fps, features, counts, path templates
    meta/stats.json                                per-feature min/max/mean/std/count
    meta/tasks.parquet                             task text (index) -> task_index
    meta/episodes/chunk-000/file-000.parquet       per episode: length, tasks, where its
                                                   rows and video frames lie
    data/chunk-000/file-000.parquet                one row per frame (many episodes a file)
    videos/observation.images.<view>/chunk-000/file-000.mp4   episodes back to back

The frame features are lerobot's defaults (``timestamp``, ``frame_index``, ``episode_index``,
``index``, ``task_index``) plus ``observation.state`` (15 float32,
:data:`~vlm_bench.vla.observation.PROPRIO_FIELDS`), ``action`` (12 float32,
:data:`~vlm_bench.vla.action.ACTION_FIELDS`) and one ``observation.images.<view>`` video per
camera.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vlm_bench.vla.action import ACTION_FIELDS
from vlm_bench.vla.observation import PROPRIO_FIELDS

CODEBASE_VERSION = "v3.0"
CHUNKS_SIZE = 1000  # files per chunk folder
DATA_FILE_SIZE_MB = 100
VIDEO_FILE_SIZE_MB = 500
DATA_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
VIDEO_PATH = "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
EPISODES_PATH = "meta/episodes/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
TASKS_PATH = "meta/tasks.parquet"
INFO_PATH = "meta/info.json"
STATS_PATH = "meta/stats.json"
VIDEO_CODEC = "h264"
PIX_FMT = "yuv420p"
ROBOT_TYPE = "aerial_manipulator_uav_panda"
STATE = "observation.state"
ACTION = "action"
IMAGE_PREFIX = "observation.images."
INDEX_FEATURES = ("timestamp", "frame_index", "episode_index", "index", "task_index")


def video_key(view: str) -> str:
    """The feature name of a camera's stream."""
    return IMAGE_PREFIX + view


def features(views: Sequence[str], size: int, fps: int) -> dict[str, dict[str, Any]]:
    """``info.json``'s ``features``: every stored feature's dtype, shape and names."""
    out: dict[str, dict[str, Any]] = {}
    for view in views:
        out[video_key(view)] = {
            "dtype": "video",
            "shape": [size, size, 3],
            "names": ["height", "width", "channels"],
            "info": {
                "video.height": size,
                "video.width": size,
                "video.codec": VIDEO_CODEC,
                "video.pix_fmt": PIX_FMT,
                "video.is_depth_map": False,
                "video.fps": fps,
                "video.channels": 3,
                "has_audio": False,
            },
        }
    out[STATE] = {"dtype": "float32", "shape": [len(PROPRIO_FIELDS)], "names": list(PROPRIO_FIELDS)}
    out[ACTION] = {"dtype": "float32", "shape": [len(ACTION_FIELDS)], "names": list(ACTION_FIELDS)}
    out["timestamp"] = {"dtype": "float32", "shape": [1], "names": None}
    for name in INDEX_FEATURES[1:]:
        out[name] = {"dtype": "int64", "shape": [1], "names": None}
    return out


def info(
    feats: Mapping[str, Any], fps: int, episodes: int, frames: int, tasks: int
) -> dict[str, Any]:
    """The whole ``meta/info.json``."""
    return {
        "codebase_version": CODEBASE_VERSION,
        "robot_type": ROBOT_TYPE,
        "total_episodes": episodes,
        "total_frames": frames,
        "total_tasks": tasks,
        "chunks_size": CHUNKS_SIZE,
        "data_files_size_in_mb": DATA_FILE_SIZE_MB,
        "video_files_size_in_mb": VIDEO_FILE_SIZE_MB,
        "fps": fps,
        "splits": {"train": f"0:{episodes}"},
        "data_path": DATA_PATH,
        "video_path": VIDEO_PATH if any(f["dtype"] == "video" for f in feats.values()) else None,
        "features": dict(feats),
    }


class RunningStats:
    """Min, max, mean and std of a feature over all frames, accumulated episode by episode
    (images per channel, scaled to [0, 1], shaped ``(3, 1, 1)`` as lerobot stores them)."""

    def __init__(self) -> None:
        self.count = 0
        """Frames seen (``count`` in stats.json)."""
        self.samples = 0
        self.total: NDArray[np.float64] | None = None
        self.squares: NDArray[np.float64] | None = None
        self.low: NDArray[np.float64] | None = None
        self.high: NDArray[np.float64] | None = None

    def add(self, values: NDArray[np.floating], frames: int | None = None) -> None:
        """Add samples (rows) of the feature's entries (columns), from ``frames`` frames
        (default: one per row)."""
        v = np.asarray(values, dtype=np.float64)
        self.samples += v.shape[0]
        self.count += v.shape[0] if frames is None else frames
        s, q, lo, hi = v.sum(0), (v * v).sum(0), v.min(0), v.max(0)
        if self.total is None or self.squares is None or self.low is None or self.high is None:
            self.total, self.squares, self.low, self.high = s, q, lo, hi
            return
        self.total += s
        self.squares += q
        self.low, self.high = np.minimum(self.low, lo), np.maximum(self.high, hi)

    def add_images(self, images: NDArray[np.uint8]) -> None:
        """Add ``(n, h, w, 3)`` uint8 frames: per-channel statistics of the values / 255."""
        self.add(images.reshape(-1, 3).astype(np.float64) / 255.0, frames=images.shape[0])

    def to_json(self, image: bool = False) -> dict[str, Any]:
        """The statistics as ``stats.json`` holds them."""
        if self.total is None or self.squares is None or self.low is None or self.high is None:
            return {}
        mean = self.total / self.samples
        std = np.sqrt(np.maximum(self.squares / self.samples - mean * mean, 0.0))

        def shaped(a: NDArray[np.float64]) -> list[Any]:
            out: list[Any] = a.reshape(3, 1, 1).tolist() if image else a.tolist()
            return out

        return {
            "min": shaped(self.low),
            "max": shaped(self.high),
            "mean": shaped(mean),
            "std": shaped(std),
            "count": [self.count],
        }
