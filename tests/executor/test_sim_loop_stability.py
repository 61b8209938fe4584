"""The simulation loop stops on an unstable state: a new bad-state warning from MuJoCo, a
non-finite position or velocity, or a speed over the configured bound; a stable state passes."""

from __future__ import annotations

import math

import mujoco
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.sim_loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.types.execution import ExecutorConfig


@pytest.fixture(scope="module")
def loop() -> SimLoop:
    episode = get_episode("standard_pick_place", 0)
    return SimLoop(episode_scene(episode, ExecutorConfig()))


@pytest.mark.parametrize(
    ("field", "index", "value", "unstable"),
    [
        ("qpos", 9, math.nan, True),
        ("qpos", 0, math.inf, True),
        ("qvel", 3, math.nan, True),
        ("qvel", 7, -math.inf, True),
        ("qvel", 2, "limit", False),  # at the bound: still stable
        ("qvel", 2, "over", True),
        ("qvel", 8, "-over", True),
        ("warning", int(mujoco.mjtWarning.mjWARN_BADQACC), 1, True),
        ("warning", int(mujoco.mjtWarning.mjWARN_CONTACTFULL), 1, False),  # not a bad state
    ],
)
def test_unstable_states_stop_the_loop(
    loop: SimLoop, field: str, index: int, value: float | str, unstable: bool
) -> None:
    d = loop.data
    qpos, qvel = d.qpos.copy(), d.qvel.copy()
    counts = d.warning.number.copy()
    limit = loop.config.max_speed_unstable
    try:
        loop._check_stable()  # the state as built is stable
        if field == "warning":
            d.warning[index].number += int(value)
        else:
            number = {"limit": limit, "over": limit * 1.001, "-over": -limit * 1.001}.get(
                str(value), value
            )
            getattr(d, field)[index] = number
        if unstable:
            with pytest.raises(SimulatorUnstable):
                loop._check_stable()
        else:
            loop._check_stable()
    finally:
        d.qpos[:], d.qvel[:] = qpos, qvel
        for k, n in enumerate(counts.tolist()):
            d.warning[k].number = n
