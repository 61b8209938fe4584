"""A small synthetic demonstrations dataset written by the real writer (no simulation)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vlm_bench.vla.demos.lerobot_writer import EpisodeData, LeRobotWriter

VIEWS = ("wrist", "overhead")
SIZE = 32
FPS = 20
LENGTHS = (25, 18, 31)
TASKS = ("Pick up the cube.", "Push the box.", "Pick up the cube.")


def synthetic_episode(k: int, n: int, task: str) -> EpisodeData:
    """Episode ``k``: smooth colour ramps (they survive H.264 nearly unchanged)."""
    rng = np.random.default_rng(k)
    states = rng.normal(size=(n, 15)).astype(np.float32)
    actions = (0.01 * states[:, :12] + rng.normal(scale=0.001, size=(n, 12))).astype(np.float32)
    ramp = np.linspace(0, 1, n)[:, None, None, None]
    base = np.array([40 + 60 * k, 120, 200 - 50 * k], dtype=np.float64)
    images = {
        v: np.broadcast_to((base * (0.5 + 0.5 * ramp)) + 10 * i, (n, SIZE, SIZE, 3))
        .astype(np.uint8)
        .copy()
        for i, v in enumerate(VIEWS)
    }
    source = {"vlm_bench/task_id": "standard_pick_place", "vlm_bench/seed": 10 + k}
    return EpisodeData(task, states, actions, images, {**source, "vlm_bench/plan_step": -1})


def write_synthetic(root: Path) -> list[EpisodeData]:
    """Write the three episodes into ``root``; returns them."""
    episodes = [
        synthetic_episode(k, n, t) for k, (n, t) in enumerate(zip(LENGTHS, TASKS, strict=True))
    ]
    writer = LeRobotWriter(root, VIEWS, SIZE, FPS)
    for episode in episodes:
        writer.add(episode)
    writer.close()
    return episodes


@pytest.fixture
def synthetic(tmp_path: Path) -> tuple[Path, list[EpisodeData]]:
    """A written synthetic dataset's folder and its episodes."""
    root = tmp_path / "demos"
    return root, write_synthetic(root)
