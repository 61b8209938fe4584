"""Build the MuJoCo scene of an episode: environment, objects, robot, cameras."""

from __future__ import annotations

import copy
from dataclasses import dataclass

import mujoco

from vlm_bench.catalog.world_catalog import environment
from vlm_bench.sim.constants import ARM_OBSERVE, GRIPPER_OPEN, PHYSICS_DT, SLEEP
from vlm_bench.sim.environment import add_environment
from vlm_bench.sim.height_views import add_third_person_cameras
from vlm_bench.sim.objects import add_object, apply_initial_state
from vlm_bench.sim.robot import add_aerial_manipulator, set_arm_qpos, set_arm_targets
from vlm_bench.sim.uav_control import GustConfig, UavController
from vlm_bench.types.episode import Episode


@dataclass
class Scene:
    """A compiled episode scene, ready to render or step."""

    episode: Episode
    spec: mujoco.MjSpec
    model: mujoco.MjModel
    data: mujoco.MjData
    controller: UavController

    def copy(self) -> Scene:
        """An independent copy of this scene's current state (model and data copied, a new
        controller with the same gusts holding the episode's start pose); cheaper than
        rebuilding it."""
        model, data = copy.copy(self.model), copy.copy(self.data)
        controller = UavController(model, data, gust=self.controller.gust)
        start = self.episode.uav_start
        controller.set_setpoint(start.pos, start.yaw_deg)
        return Scene(self.episode, self.spec, model, data, controller)


def build_spec(episode: Episode) -> mujoco.MjSpec:
    """The episode's MjSpec (uncompiled)."""
    spec = mujoco.MjSpec()
    spec.modelname = f"{episode.task_id}_seed{episode.seed}"
    spec.option.timestep = PHYSICS_DT
    if SLEEP:
        spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    add_environment(spec, environment(episode.environment), episode.lighting)
    for obj in episode.objects:
        add_object(spec, obj)
    add_aerial_manipulator(spec, episode.uav_start)
    add_third_person_cameras(spec, episode)
    return spec


def build_scene(episode: Episode, gust: GustConfig | None = None) -> Scene:
    """Compile the episode's scene at its start state: UAV holding its start pose, the arm in
    the observe pose (wrist camera looking ahead), gripper open."""
    spec = build_spec(episode)
    model = spec.compile()
    data = mujoco.MjData(model)
    for obj in episode.objects:
        apply_initial_state(model, data, obj)
    set_arm_qpos(model, data, ARM_OBSERVE, GRIPPER_OPEN)
    set_arm_targets(model, data, ARM_OBSERVE, GRIPPER_OPEN)
    controller = UavController(model, data, gust=gust)
    controller.set_setpoint(episode.uav_start.pos, episode.uav_start.yaw_deg)
    mujoco.mj_forward(model, data)
    return Scene(episode=episode, spec=spec, model=model, data=data, controller=controller)
