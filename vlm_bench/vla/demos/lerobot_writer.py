"""Streams demonstrations into a LeRobotDataset v3.0 folder (:mod:`.lerobot_format`).

Episodes are appended one at a time: their frames to the open data Parquet file (one row
group per episode) and to each camera's open MP4 (H.264, yuv420p, through imageio-ffmpeg),
back to back; a file that has passed its size limit is closed and the next episode starts
a new one. The metadata (episodes, tasks, statistics, info) is written by :meth:`close`.
Requires ``pyarrow`` and ``imageio-ffmpeg`` (the ``demos`` extra).
"""

from __future__ import annotations

import importlib.util
import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vlm_bench.errors import MissingExtraError
from vlm_bench.vla.demos import lerobot_format as fmt

MB = 1024 * 1024
GOP = 10  # frames between key frames: lerobot seeks to a frame's timestamp


def require_writer_packages() -> None:
    """Raise :class:`MissingExtraError` unless pyarrow and imageio-ffmpeg import."""
    for module, package in (("pyarrow", "pyarrow"), ("imageio_ffmpeg", "imageio-ffmpeg")):
        if importlib.util.find_spec(module) is None:
            raise MissingExtraError(package, "demos")


@dataclass(frozen=True)
class EpisodeData:
    """One episode to write: per-frame arrays and its task text."""

    task: str
    states: NDArray[np.float32]
    """``(n, 15)``."""
    actions: NDArray[np.float32]
    """``(n, 12)``."""
    images: dict[str, NDArray[np.uint8]]
    """View -> ``(n, size, size, 3)``."""
    source: dict[str, Any] = field(default_factory=dict)
    """Extra columns of its row in the episodes table (where it came from)."""

    def __len__(self) -> int:
        return int(self.actions.shape[0])


class _Video:
    """One camera's open MP4 file and where the next episode starts in it."""

    def __init__(self, root: Path, key: str, size: int, fps: int) -> None:
        self.root, self.key, self.size, self.fps = root, key, size, fps
        self.file_index = -1
        self.frames = 0
        self._gen: Any = None
        self._path = root

    def _open(self) -> None:
        import imageio_ffmpeg

        self.file_index += 1
        self.frames = 0
        rel = fmt.VIDEO_PATH.format(video_key=self.key, chunk_index=0, file_index=self.file_index)
        self._path = self.root / rel
        self._path.parent.mkdir(parents=True, exist_ok=True)
        self._gen = imageio_ffmpeg.write_frames(
            str(self._path),
            (self.size, self.size),
            fps=self.fps,
            codec="libx264",
            pix_fmt_out=fmt.PIX_FMT,
            macro_block_size=1,
            quality=None,
            output_params=["-g", str(GOP), "-crf", "23", "-preset", "veryfast"],
            ffmpeg_log_level="error",
        )
        self._gen.send(None)

    def append(self, frames: NDArray[np.uint8]) -> dict[str, Any]:
        """Write an episode's frames; returns its episodes-table columns."""
        if self._gen is None or _size(self._path) > fmt.VIDEO_FILE_SIZE_MB * MB:
            self.close()
            self._open()
        start = self.frames
        for frame in frames:
            self._gen.send(np.ascontiguousarray(frame))
        self.frames += len(frames)
        prefix = f"videos/{self.key}/"
        return {
            prefix + "chunk_index": 0,
            prefix + "file_index": self.file_index,
            prefix + "from_timestamp": start / self.fps,
            prefix + "to_timestamp": self.frames / self.fps,
        }

    def close(self) -> None:
        if self._gen is not None:
            self._gen.close()
            self._gen = None


class LeRobotWriter:
    """Writes episodes into ``root`` (an empty or new folder).

    Args:
        root: The dataset folder.
        views: Cameras recorded (one video feature each).
        size: Image side (px).
        fps: Frames per second of the recording.
    """

    def __init__(self, root: Path, views: Sequence[str], size: int, fps: int) -> None:
        require_writer_packages()
        self.root, self.views, self.size, self.fps = root, tuple(views), size, fps
        self.features = fmt.features(self.views, size, fps)
        self.tasks: dict[str, int] = {}
        self.episodes: list[dict[str, Any]] = []
        self.frames = 0
        self._videos = {v: _Video(root, fmt.video_key(v), size, fps) for v in self.views}
        self._stats = {name: fmt.RunningStats() for name in self.features}
        self._data: Any = None
        self._data_index = -1
        self._data_path = root

    def add(self, episode: EpisodeData) -> int:
        """Append one episode; returns its ``episode_index``."""
        import pyarrow as pa

        n, index = len(episode), len(self.episodes)
        task_index = self.tasks.setdefault(episode.task, len(self.tasks))
        columns: dict[str, Any] = {
            fmt.STATE: _fixed(episode.states),
            fmt.ACTION: _fixed(episode.actions),
            "timestamp": pa.array(np.arange(n, dtype=np.float32) / np.float32(self.fps)),
            "frame_index": pa.array(np.arange(n, dtype=np.int64)),
            "episode_index": pa.array(np.full(n, index, dtype=np.int64)),
            "index": pa.array(np.arange(self.frames, self.frames + n, dtype=np.int64)),
            "task_index": pa.array(np.full(n, task_index, dtype=np.int64)),
        }
        self._write_rows(pa.table(columns))
        row: dict[str, Any] = {
            "episode_index": index,
            "tasks": [episode.task],
            "length": n,
            "data/chunk_index": 0,
            "data/file_index": self._data_index,
            "dataset_from_index": self.frames,
            "dataset_to_index": self.frames + n,
        }
        for view, video in self._videos.items():
            row.update(video.append(episode.images[view]))
            self._stats[fmt.video_key(view)].add_images(episode.images[view][::5])
        row["meta/episodes/chunk_index"] = 0
        row["meta/episodes/file_index"] = 0
        row.update(episode.source)
        self.episodes.append(row)
        self._add_stats(episode, index, task_index)
        self.frames += n
        return index

    def _add_stats(self, episode: EpisodeData, index: int, task_index: int) -> None:
        n = len(episode)
        self._stats[fmt.STATE].add(episode.states)
        self._stats[fmt.ACTION].add(episode.actions)
        self._stats["timestamp"].add(np.arange(n, dtype=np.float64)[:, None] / self.fps)
        self._stats["frame_index"].add(np.arange(n, dtype=np.float64)[:, None])
        self._stats["episode_index"].add(np.full((n, 1), float(index)))
        self._stats["index"].add(np.arange(self.frames, self.frames + n, dtype=np.float64)[:, None])
        self._stats["task_index"].add(np.full((n, 1), float(task_index)))

    def _write_rows(self, table: Any) -> None:
        import pyarrow.parquet as pq

        full = self._data is not None and (_size(self._data_path) > fmt.DATA_FILE_SIZE_MB * MB)
        if self._data is None or full:
            if self._data is not None:
                self._data.close()
            self._data_index += 1
            rel = fmt.DATA_PATH.format(chunk_index=0, file_index=self._data_index)
            self._data_path = self.root / rel
            self._data_path.parent.mkdir(parents=True, exist_ok=True)
            self._data = pq.ParquetWriter(self._data_path, table.schema)
        self._data.write_table(table)

    def close(self) -> None:
        """Close the open files and write the metadata."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        if self._data is not None:
            self._data.close()
            self._data = None
        for video in self._videos.values():
            video.close()
        meta = self.root / "meta"
        meta.mkdir(parents=True, exist_ok=True)
        episodes_path = self.root / fmt.EPISODES_PATH.format(chunk_index=0, file_index=0)
        episodes_path.parent.mkdir(parents=True, exist_ok=True)
        pq.write_table(pa.Table.from_pylist(self.episodes), episodes_path)
        import pandas as pd

        # the task text is the index: lerobot looks a task's index up by its text
        tasks = pd.DataFrame({"task_index": list(self.tasks.values())}, index=list(self.tasks))
        tasks.index.name = "task"
        tasks.to_parquet(self.root / fmt.TASKS_PATH)
        stats = {
            name: s.to_json(image=self.features[name]["dtype"] == "video")
            for name, s in self._stats.items()
            if s.count
        }
        (self.root / fmt.STATS_PATH).write_text(json.dumps(stats, indent=2) + "\n")
        info = fmt.info(self.features, self.fps, len(self.episodes), self.frames, len(self.tasks))
        (self.root / fmt.INFO_PATH).write_text(json.dumps(info, indent=4) + "\n")


def _fixed(values: NDArray[np.float32]) -> Any:
    """A ``(n, k)`` float32 array as an Arrow fixed-size list column of length ``k``."""
    import pyarrow as pa

    flat = pa.array(np.ascontiguousarray(values, dtype=np.float32).reshape(-1))
    return pa.FixedSizeListArray.from_arrays(flat, values.shape[1])


def _size(path: Path) -> int:
    """Bytes written to ``path`` so far (ffmpeg creates its output a little after starting)."""
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return 0
