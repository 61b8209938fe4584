"""An exported demonstrations dataset read back from disk with the project's own packages
(pyarrow, imageio-ffmpeg): the metadata, each episode's frames, its video frames decoded.

lerobot's ``LeRobotDataset`` reads the same folder (benchmarks/lerobot_check.py); this reader
serves the replay check and plain-torch training without lerobot's environment.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vlm_bench.errors import ConfigError
from vlm_bench.vla.demos import lerobot_format as fmt
from vlm_bench.vla.demos.lerobot_writer import require_writer_packages


@dataclass(frozen=True)
class StoredEpisode:
    """One episode of a stored dataset."""

    index: int
    task: str
    row: dict[str, Any]
    """Its row of the episodes table (lengths, file positions, source columns)."""
    states: NDArray[np.float32]
    actions: NDArray[np.float32]


class DemoDataset:
    """A demonstrations dataset folder (``meta/info.json`` and the files it names).

    Raises:
        ConfigError: ``root`` holds no dataset.
    """

    def __init__(self, root: Path) -> None:
        require_writer_packages()
        import pyarrow.parquet as pq

        self.root = root
        info_path = root / fmt.INFO_PATH
        if not info_path.is_file():
            raise ConfigError(f"{root} holds no demonstrations dataset ({fmt.INFO_PATH} missing)")
        self.info: dict[str, Any] = json.loads(info_path.read_text())
        self.fps = int(self.info["fps"])
        episodes = sorted((root / "meta" / "episodes").glob("*/*.parquet"))
        self.episodes: list[dict[str, Any]] = [
            r for path in episodes for r in pq.read_table(path).to_pylist()
        ]
        self.views = [
            k.removeprefix(fmt.IMAGE_PREFIX)
            for k, f in self.info["features"].items()
            if f["dtype"] == "video"
        ]
        self._data: dict[int, Any] = {}

    def __len__(self) -> int:
        return len(self.episodes)

    def _table(self, file_index: int) -> Any:
        import pyarrow.parquet as pq

        if file_index not in self._data:
            rel = fmt.DATA_PATH.format(chunk_index=0, file_index=file_index)
            self._data[file_index] = pq.read_table(self.root / rel)
        return self._data[file_index]

    def episode(self, index: int) -> StoredEpisode:
        """Episode ``index``'s task, state and action arrays."""
        row = self.episodes[index]
        table = self._table(int(row["data/file_index"]))
        mask = np.asarray(table.column("episode_index").to_numpy()) == index
        rows = np.flatnonzero(mask)
        part = table.take(rows)
        states = np.array(part.column(fmt.STATE).to_pylist(), dtype=np.float32)
        actions = np.array(part.column(fmt.ACTION).to_pylist(), dtype=np.float32)
        return StoredEpisode(index, str(row["tasks"][0]), row, states, actions)

    def images(self, index: int, view: str) -> NDArray[np.uint8]:
        """Episode ``index``'s frames of ``view``, decoded: ``(n, h, w, 3)`` uint8."""
        import imageio_ffmpeg

        row = self.episodes[index]
        key = fmt.video_key(view)
        rel = fmt.VIDEO_PATH.format(
            video_key=key, chunk_index=0, file_index=int(row[f"videos/{key}/file_index"])
        )
        first = round(float(row[f"videos/{key}/from_timestamp"]) * self.fps)
        n = int(row["length"])
        reader = imageio_ffmpeg.read_frames(
            str(self.root / rel), output_params=["-fps_mode", "passthrough"]
        )
        meta = next(reader)
        w, h = meta["size"]
        out = []
        try:
            for k, raw in enumerate(reader):
                if k >= first + n:
                    break
                if k >= first:
                    out.append(np.frombuffer(raw, dtype=np.uint8).reshape(h, w, 3))
        finally:
            reader.close()
        return np.stack(out)
