"""A gymnasium environment of one benchmark task for VLA pipelines
(docs/design.md#hierarchical-use).

Each :meth:`~AerialManipulationEnv.step` applies the 12-D :class:`VlaAction` (4 UAV setpoint
deltas, 7 joint targets, gripper) for one 50 ms control period. The observation is a dict of the
configured camera images (``(size, size, 3)`` uint8, keyed by camera name) and ``proprio`` (15
float32 values, :data:`~vlm_bench.vla.observation.PROPRIO_FIELDS`). The reward is the
fraction of the task's goals that hold in the current (not settled) state, in [0, 1]; the
episode terminates when all hold or the simulator becomes unstable, and is truncated after
``max_episode_steps`` steps.

The episode is fixed until changed: ``reset()`` rebuilds the same task and episode seed;
``reset(seed=s)`` switches to episode seed ``s`` (and seeds ``np_random``); the options
``task_id``, ``seed`` and ``variant`` select another task, episode seed or instruction variant.
Requires the ``gym`` extra (``pip install 'vlm-bench[gym]'``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray
from pydantic import Field, ValidationError

from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError, MissingExtraError, UnknownNameError, first_problem
from vlm_bench.executor.goals import check_goals
from vlm_bench.executor.sim_loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim.constants import CAM_OVERHEAD, CAMERAS
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.snapshot_render import check_views
from vlm_bench.types.base import Frozen
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.task import InstructionVariant
from vlm_bench.vla.action import VlaAction, action_bounds, apply_action, joint_limits
from vlm_bench.vla.observation import (
    PROPRIO_SIZE,
    ObservationConfig,
    ObservationRenderer,
)

try:
    import gymnasium as gym
    from gymnasium import spaces
except ImportError as err:  # the optional extra is missing
    raise MissingExtraError("gymnasium", "gym") from err

Observation = dict[str, Any]  # camera name -> uint8 image, "proprio" -> float32 vector
DEFAULT_ENV_RENDER_SIZE = 64
DEFAULT_MAX_EPISODE_STEPS = 1200  # 60 s of simulated time
RENDER_MODES = ("rgb_array",)


class ResetOptions(Frozen):
    """What ``reset(options=...)`` may select; unset fields keep the current choice."""

    task_id: str | None = Field(default=None, description="Task to switch to.")
    seed: int | None = Field(default=None, ge=0, description="Episode seed (layout, UAV start).")
    variant: InstructionVariant | None = Field(default=None, description="Instruction variant.")


class AerialManipulationEnv(gym.Env[Observation, NDArray[np.float32]]):
    """One task of the benchmark as a gymnasium environment (see the module docstring).

    Args:
        task_id: Benchmark task id.
        seed: Episode seed (layout, UAV start, lighting).
        variant: Instruction variant reported in ``info["instruction"]``.
        render_size: Side of the observation images (px).
        views: Cameras in the observation (fewer is faster; ``()``: proprioception only).
        max_episode_steps: Steps (50 ms each) before the episode is truncated.
        config: Executor settings (gusts, instability threshold).
        render_mode: ``"rgb_array"`` (``render()`` returns a frame) or ``None``.
        render_camera: Camera that :meth:`render` shows.
        frame_size: Side of the :meth:`render` frame (px).
        shadows: Render shadows (about 2.5x slower on CPU).
    """

    # gymnasium declares ``metadata`` as a plain attribute read from the class (not a ClassVar).
    metadata: dict[str, Any] = {"render_modes": list(RENDER_MODES), "render_fps": 20}  # noqa: RUF012

    def __init__(
        self,
        task_id: str = "standard_pick_place",
        seed: int = 0,
        variant: InstructionVariant = "explicit",
        render_size: int = DEFAULT_ENV_RENDER_SIZE,
        views: Sequence[str] = CAMERAS,
        max_episode_steps: int = DEFAULT_MAX_EPISODE_STEPS,
        config: ExecutorConfig | None = None,
        *,
        render_mode: str | None = "rgb_array",
        render_camera: str = CAM_OVERHEAD,
        frame_size: int = 256,
        shadows: bool = False,
    ) -> None:
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise UnknownNameError("render mode", render_mode, RENDER_MODES)
        if max_episode_steps < 1:
            raise ConfigError(f"max_episode_steps must be >= 1, got {max_episode_steps}")
        check_views([render_camera])
        self.render_mode = render_mode
        self.render_camera = render_camera
        self.frame_size = frame_size
        self.variant: InstructionVariant = variant
        self.max_episode_steps = max_episode_steps
        self.config = config or ExecutorConfig()
        self.observation_config = ObservationConfig(
            views=tuple(views), size=render_size, shadows=shadows
        )
        self.episode: Episode = get_episode(task_id, seed)
        low, high = action_bounds(*joint_limits(episode_scene(self.episode, self.config).model))
        self.action_space = spaces.Box(low.astype(np.float32), high.astype(np.float32))
        images = {
            view: spaces.Box(0, 255, (render_size, render_size, 3), np.uint8)
            for view in self.observation_config.views
        }
        proprio = spaces.Box(-np.inf, np.inf, (PROPRIO_SIZE,), np.float32)
        self.observation_space = spaces.Dict({**images, "proprio": proprio})
        self._renderer = SnapshotRenderer(shadows=shadows)
        self._observer = ObservationRenderer(self.observation_config, self._renderer)
        self._loop: SimLoop | None = None
        self._steps = 0
        self._unstable = False

    # ---- gymnasium API -------------------------------------------------------------------
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Observation, dict[str, Any]]:
        """Build the episode's scene afresh; returns the first observation and the task info.

        ``info`` holds ``task_id``, ``episode_seed``, ``instruction``, ``object_ids`` (ids a
        plan may name), ``gt_plan`` (the ground-truth plan steps) and ``goals`` (each goal's
        truth now).
        """
        super().reset(seed=seed)
        try:
            opts = ResetOptions.model_validate(options or {})
        except ValidationError as err:
            where, why, _ = first_problem(err)
            valid = ", ".join(ResetOptions.model_fields)
            raise ConfigError(f"reset option {where!r}: {why}; valid options: {valid}") from err
        task = opts.task_id or self.episode.task_id
        episode_seed = opts.seed if opts.seed is not None else seed
        # gymnasium passes numpy integers at times; episodes take plain ints
        episode_seed = self.episode.seed if episode_seed is None else int(episode_seed)
        if (task, episode_seed) != (self.episode.task_id, self.episode.seed):
            self.episode = get_episode(task, episode_seed)
        self.variant = opts.variant or self.variant
        self._loop = SimLoop(episode_scene(self.episode, self.config), self.config)
        self._steps = 0
        self._unstable = False
        episode = self.episode
        info: dict[str, Any] = {
            "task_id": episode.task_id,
            "episode_seed": episode.seed,
            "instruction": episode.instruction(self.variant),
            "object_ids": episode.object_ids(),
            "gt_plan": episode.gt_plan,
            "goals": self._goals(self._loop),
        }
        return self._observation(self._loop), info

    def step(
        self, action: NDArray[np.float32]
    ) -> tuple[Observation, float, bool, bool, dict[str, Any]]:
        """Apply ``action`` (12 values, clipped to the action space) for one control period.

        ``info`` holds ``goals`` (each goal's truth), ``success`` (all hold), ``sim_time_s``,
        ``collisions`` (non-robot geoms the robot touched in this step) and, after a blow-up,
        ``failure``.
        """
        loop = self._live_loop()
        command = VlaAction.from_array(action)
        self._steps += 1
        truncated = self._steps >= self.max_episode_steps
        try:
            apply_action(loop, command)
        except SimulatorUnstable as err:
            self._unstable = True
            info: dict[str, Any] = {
                "goals": tuple(False for _ in self.episode.goals),
                "success": False,
                "sim_time_s": loop.time,
                "collisions": loop.take_collisions(),
                "failure": str(err),
            }
            return self._observation(loop), 0.0, True, truncated, info
        goals = self._goals(loop)
        success = bool(goals) and all(goals)
        reward = sum(goals) / len(goals) if goals else 0.0
        info = {
            "goals": goals,
            "success": success,
            "sim_time_s": loop.time,
            "collisions": loop.take_collisions(),
        }
        return self._observation(loop), reward, success, truncated, info

    def render(self) -> NDArray[np.uint8] | None:
        """An RGB frame (``frame_size`` square) of ``render_camera``; ``None`` without a mode."""
        if self.render_mode is None:
            return None
        loop = self._require_loop()
        return self._renderer.render(loop.model, loop.data, self.render_camera, self.frame_size)

    def close(self) -> None:
        """Free the GL resources (safe to call twice; the env renders again if used)."""
        self._renderer.close()

    # ---- helpers -------------------------------------------------------------------------
    @property
    def loop(self) -> SimLoop:
        """The simulation loop of the current episode (after :meth:`reset`)."""
        return self._require_loop()

    def _require_loop(self) -> SimLoop:
        if self._loop is None:
            raise ConfigError("call reset() before step() or render()")
        return self._loop

    def _goals(self, loop: SimLoop) -> tuple[bool, ...]:
        """Each goal's truth, judged on a copy of the data: the check recomputes positions,
        which must not reach the simulation (a replay of recorded actions then follows the
        recorded execution exactly)."""
        scratch = mujoco.MjData(loop.model)
        mujoco.mj_copyData(scratch, loop.model, loop.data)
        return check_goals(self.episode, loop.model, scratch)

    def _live_loop(self) -> SimLoop:
        loop = self._require_loop()
        if self._unstable:
            raise ConfigError("the simulation became unstable; call reset() to start again")
        return loop

    def _observation(self, loop: SimLoop) -> Observation:
        obs = self._observer.observe(loop, self.episode.instruction(self.variant)).arrays()
        obs["proprio"] = np.nan_to_num(obs["proprio"], posinf=0.0, neginf=0.0)
        return obs
