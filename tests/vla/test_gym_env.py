"""The gymnasium environment: API conformance, spaces, reward from goals, episode ends."""

from __future__ import annotations

import math
import re
import subprocess
import sys
import warnings
from collections.abc import Iterator
from pathlib import Path

import mujoco
import numpy as np
import pytest

pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env

from vlm_bench.errors import ConfigError, VlmBenchError
from vlm_bench.executor import SimulatorUnstable
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.vla import Proprioception, VlaAction
from vlm_bench.vla.action import MAX_UAV_STEP_M
from vlm_bench.vla.gym_env import AerialManipulationEnv

DOCS = Path(__file__).resolve().parents[2] / "docs" / "hierarchical.md"
CAN_TASK = "cylinder_manipulation"  # goals: on(meat_can, white_plate), upright(meat_can)


@pytest.fixture
def env() -> Iterator[AerialManipulationEnv]:
    env = AerialManipulationEnv(render_size=16, frame_size=24, max_episode_steps=50)
    yield env
    env.close()


def _hold(obs: dict[str, np.ndarray]) -> np.ndarray:
    return VlaAction.holding(Proprioception.from_array(obs["proprio"])).to_array()


def test_passes_the_gymnasium_env_checker() -> None:
    env = AerialManipulationEnv(render_size=32, frame_size=32)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # advice on unbounded/unnormalised Box spaces
            check_env(env)
    finally:
        env.close()


def test_reset_and_step_match_the_spaces(env: AerialManipulationEnv) -> None:
    obs, info = env.reset()
    assert env.observation_space.contains(obs)
    assert set(obs) == {*c.CAMERAS, "proprio"}
    assert obs["overhead"].shape == (16, 16, 3) and obs["proprio"].dtype == np.float32
    assert env.action_space.shape == (12,)
    assert info["task_id"] == "standard_pick_place" and info["episode_seed"] == 0
    assert info["instruction"] == env.episode.instruction("explicit")
    assert info["object_ids"] == env.episode.object_ids()
    assert info["gt_plan"] == env.episode.gt_plan
    obs, reward, terminated, truncated, info = env.step(_hold(obs))
    assert env.observation_space.contains(obs)
    assert (reward, terminated, truncated) == (0.0, False, False)
    assert info["goals"] == (False,) and info["sim_time_s"] == pytest.approx(c.CONTROL_DT)
    frame = env.render()
    assert frame is not None and frame.shape == (24, 24, 3) and frame.dtype == np.uint8


def test_views_select_the_images() -> None:
    env = AerialManipulationEnv(views=("wrist",), render_size=8)
    try:
        obs, _ = env.reset()
        assert set(obs) == {"wrist", "proprio"} and obs["wrist"].shape == (8, 8, 3)
        assert set(env.observation_space.spaces) == {"wrist", "proprio"}
    finally:
        env.close()


def test_action_moves_the_setpoint_in_the_body_frame(env: AerialManipulationEnv) -> None:
    obs, _ = env.reset()
    start = env.loop.controller.setpoint.copy()
    action = _hold(obs)
    action[0] = 1.0  # forward, clipped to the per-step bound
    env.step(action)
    yaw = math.radians(env.episode.uav_start.yaw_deg)
    moved = env.loop.controller.setpoint - start
    assert np.allclose(moved, [MAX_UAV_STEP_M * math.cos(yaw), MAX_UAV_STEP_M * math.sin(yaw), 0])


def test_reward_is_the_fraction_of_goals_that_hold() -> None:
    env = AerialManipulationEnv(CAN_TASK, views=(), max_episode_steps=10)
    try:
        obs, info = env.reset()
        assert info["goals"] == (False, True)
        _, reward, terminated, _, info = env.step(_hold(obs))
        assert (reward, terminated, info["success"]) == (0.5, False, False)
        # Move the can onto the plate: both goals hold, the episode terminates.
        model, data = env.loop.model, env.loop.data
        _, top = object_bounds(model, data, "white_plate", solid_only=True)
        plate = data.body("white_plate").xpos
        adr = model.jnt_qposadr[model.body("meat_can").jntadr[0]]
        data.qpos[adr : adr + 3] = [plate[0], plate[1], top[2] + 0.002]
        mujoco.mj_forward(model, data)
        _, reward, terminated, _, info = env.step(_hold(obs))
        assert (reward, terminated, info["success"]) == (1.0, True, True)
        assert info["goals"] == (True, True)
    finally:
        env.close()


def test_truncates_at_the_step_limit() -> None:
    env = AerialManipulationEnv(views=(), max_episode_steps=3)
    try:
        obs, _ = env.reset()
        ends = [env.step(_hold(obs))[3] for _ in range(3)]
        assert ends == [False, False, True]
        env.reset()  # a reset starts the count again
        assert env.step(_hold(obs))[3] is False
    finally:
        env.close()


def test_reset_selects_task_seed_and_variant(env: AerialManipulationEnv) -> None:
    _, info = env.reset(options={"task_id": CAN_TASK, "seed": 2, "variant": "implicit"})
    assert (info["task_id"], info["episode_seed"]) == (CAN_TASK, 2)
    assert info["instruction"] == env.episode.instruction("implicit")
    _, info = env.reset(seed=3)
    assert (info["task_id"], info["episode_seed"]) == (CAN_TASK, 3)
    _, again = env.reset()  # the episode stays until changed
    assert again["episode_seed"] == 3
    assert np.allclose(env.loop.uav_position(), env.episode.uav_start.pos)
    with pytest.raises(ConfigError, match=r"'task'.*valid options: task_id, seed, variant"):
        env.reset(options={"task": CAN_TASK})


def test_instability_terminates_and_needs_a_reset(
    env: AerialManipulationEnv, monkeypatch: pytest.MonkeyPatch
) -> None:
    obs, _ = env.reset()

    def blow_up() -> None:
        raise SimulatorUnstable("simulator unstable")

    monkeypatch.setattr(env.loop, "control_step", blow_up)
    obs, reward, terminated, _, info = env.step(_hold(obs))
    assert (reward, terminated, info["failure"]) == (0.0, True, "simulator unstable")
    assert env.observation_space.contains(obs)
    with pytest.raises(ConfigError, match="reset"):
        env.step(_hold(obs))
    env.reset()
    env.step(_hold(obs))


def test_step_before_reset_and_bad_arguments_raise() -> None:
    env = AerialManipulationEnv(views=())
    with pytest.raises(ConfigError, match="reset"):
        env.step(np.zeros(12, dtype=np.float32))
    with pytest.raises(VlmBenchError, match="valid: overhead, side, uav, wrist"):
        AerialManipulationEnv(views=("nadir",))
    with pytest.raises(VlmBenchError, match="rgb_array"):
        AerialManipulationEnv(render_mode="human")
    assert AerialManipulationEnv(views=(), render_mode=None).render() is None


def test_importing_the_executor_and_vla_does_not_import_gymnasium() -> None:
    code = "import sys, vlm_bench.executor, vlm_bench.vla; print('gymnasium' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_the_documented_env_loop_runs() -> None:
    (_, example) = re.findall(r"```python\n(.*?)```", DOCS.read_text(), re.S)
    scope: dict[str, object] = {"__name__": "docs_example"}
    exec(compile(example, str(DOCS), "exec"), scope)
    frame = scope["frame"]
    assert isinstance(frame, np.ndarray) and frame.shape == (256, 256, 3)
