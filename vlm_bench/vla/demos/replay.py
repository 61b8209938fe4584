"""Replay a stored demonstration's actions in the gym environment (docs/demos.md#replay).

The environment is reset to the demonstration's episode (its task and seed, from the
episodes table) and steps through the recorded actions; the replay succeeds when the task's
goals hold after the last action, the state in which the recording's execution was judged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlm_bench.errors import ConfigError
from vlm_bench.executor.goals import check_goals
from vlm_bench.vla.demos.config import SOURCE_SEED, SOURCE_STEP, SOURCE_TASK
from vlm_bench.vla.demos.reader import DemoDataset


@dataclass(frozen=True)
class ReplayResult:
    """How a replay ended."""

    episode_index: int
    task_id: str
    seed: int
    success: bool
    """The goals hold after the last recorded action."""
    max_state_error: float
    """Largest difference between a replayed and a recorded state entry."""


def replay_episode(dataset: DemoDataset, index: int) -> ReplayResult:
    """Replay episode ``index`` of ``dataset`` (a whole execution) in the gym environment.

    Raises:
        ConfigError: The episode is one ARM step of an execution (it starts mid-way).
        MissingExtraError: gymnasium is missing (the ``gym`` extra).
    """
    from vlm_bench.vla.gym_env import AerialManipulationEnv

    stored = dataset.episode(index)
    row = stored.row
    if int(row.get(SOURCE_STEP, -1)) != -1:
        raise ConfigError(f"episode {index} is one ARM step; only whole executions replay")
    task_id, seed = str(row[SOURCE_TASK]), int(row[SOURCE_SEED])
    n = len(stored.actions)
    env = AerialManipulationEnv(task_id, seed, views=(), render_mode=None, max_episode_steps=n + 1)
    try:
        obs, _ = env.reset()
        error = float(np.abs(obs["proprio"] - stored.states[0]).max())
        for k, action in enumerate(stored.actions):
            if k:
                error = max(error, float(np.abs(obs["proprio"] - stored.states[k]).max()))
            obs, _, _, _, info = env.step(action)
            if "failure" in info:
                break
        loop = env.loop
        success = all(check_goals(env.episode, loop.model, loop.data))
    finally:
        env.close()
    return ReplayResult(index, task_id, seed, success, error)
