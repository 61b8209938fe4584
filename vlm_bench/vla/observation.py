"""What a low-level (VLA) policy sees: camera images and the robot's proprioception.

The same observation feeds the hierarchical API (:mod:`vlm_bench.vla.hierarchical`) and
the gymnasium environment (:mod:`vlm_bench.vla.gym_env`); :meth:`VlaObservation.arrays`
gives the environment's dict form, so a policy trained on the environment runs in a plan too.
Rendering dominates the cost on CPU (~25 ms per view without shadows, ~60 ms with, nearly
independent of the size), so request only the views a policy uses.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, field_validator

from vlm_bench.errors import ConfigError
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import CAMERAS, UAV_FREEJOINT
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.robot import arm_qpos, gripper_opening
from vlm_bench.sim.snapshot_render import check_views, render_scene
from vlm_bench.types.base import Frozen, Vec3
from vlm_bench.types.plan import ArmStep

JointAngles = tuple[float, float, float, float, float, float, float]
PROPRIO_FIELDS = (
    *("uav_x", "uav_y", "uav_z", "uav_yaw", "uav_vx", "uav_vy", "uav_vz"),
    *(f"joint{i}" for i in range(1, 8)),
    "gripper",
)
"""Names of the entries of :meth:`Proprioception.to_array`, in order."""
PROPRIO_SIZE = len(PROPRIO_FIELDS)
DEFAULT_RENDER_SIZE = 128


class ObservationConfig(Frozen):
    """Which images an observation carries and how they are rendered."""

    views: tuple[str, ...] = Field(
        default=CAMERAS, description="Cameras to render (uav, wrist, overhead, side); () = none."
    )
    size: int = Field(default=DEFAULT_RENDER_SIZE, ge=1, le=1024, description="Image side (px).")
    shadows: bool = Field(default=False, description="Render shadows (~2.5x slower on CPU).")
    labels: bool = Field(
        default=False, description="Draw the set-of-marks labels on the third-person views."
    )

    @field_validator("views")
    @classmethod
    def _known_views(cls, views: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(check_views(views))


class Proprioception(Frozen):
    """The robot's state as a policy sees it."""

    uav_pos: Vec3 = Field(description="UAV body position (m, world).")
    uav_yaw: float = Field(description="UAV heading (rad, CCW from world +x).")
    uav_velocity: Vec3 = Field(description="UAV linear velocity (m/s, world).")
    joints: JointAngles = Field(description="Angles of the 7 arm joints (rad).")
    gripper: float = Field(description="Opening of each finger (m; 0 closed, 0.04 open).")

    def to_array(self) -> NDArray[np.float32]:
        """The 15 values in :data:`PROPRIO_FIELDS` order."""
        values = [*self.uav_pos, self.uav_yaw, *self.uav_velocity, *self.joints, self.gripper]
        return np.array(values, dtype=np.float32)

    @classmethod
    def from_array(cls, values: Sequence[float] | NDArray[np.floating]) -> Proprioception:
        """Inverse of :meth:`to_array`."""
        v = [float(x) for x in np.asarray(values, dtype=np.float64).reshape(-1)]
        if len(v) != PROPRIO_SIZE:
            raise ConfigError(f"proprioception has {PROPRIO_SIZE} values, got {len(v)}")
        return cls(
            uav_pos=(v[0], v[1], v[2]),
            uav_yaw=v[3],
            uav_velocity=(v[4], v[5], v[6]),
            joints=(v[7], v[8], v[9], v[10], v[11], v[12], v[13]),
            gripper=v[14],
        )


def read_proprioception(loop: SimLoop) -> Proprioception:
    """The current proprioception of ``loop``'s robot."""
    pos = loop.uav_position()
    dof = int(loop.model.joint(UAV_FREEJOINT).dofadr[0])
    vel = [float(v) for v in loop.data.qvel[dof : dof + 3]]
    q = [float(v) for v in arm_qpos(loop.model, loop.data)]
    return Proprioception(
        uav_pos=(float(pos[0]), float(pos[1]), float(pos[2])),
        uav_yaw=float(np.radians(loop.uav_yaw_deg())),
        uav_velocity=(vel[0], vel[1], vel[2]),
        joints=(q[0], q[1], q[2], q[3], q[4], q[5], q[6]),
        gripper=gripper_opening(loop.model, loop.data),
    )


@dataclass(frozen=True)
class VlaObservation:
    """One control step's observation for a policy driving an ARM step.

    Attributes:
        images: Camera name to ``(size, size, 3)`` uint8 RGB image (the configured views).
        proprio: The robot's state.
        instruction: The episode's task instruction.
        step: The ARM step being executed (``None`` outside a plan, e.g. in the gym env).
        step_index: Control steps already taken in this ARM step (0 at its start).
        time_s: Simulated time (s).
    """

    images: Mapping[str, NDArray[np.uint8]]
    proprio: Proprioception
    instruction: str
    step: ArmStep | None = None
    step_index: int = 0
    time_s: float = 0.0

    @property
    def step_text(self) -> str:
        """The ARM step as a short command, e.g. ``pick gray_cube`` or ``push a to b``."""
        if self.step is None:
            return ""
        text = f"{self.step.skill} {self.step.object}"
        return f"{text} to {self.step.target}" if self.step.target else text

    def arrays(self) -> dict[str, NDArray[np.generic]]:
        """The gym environment's observation: each image by view, and ``proprio`` (float32)."""
        return {**self.images, "proprio": self.proprio.to_array()}


class ObservationRenderer:
    """Renders observations of a loop's scene, reusing one GL context.

    Args:
        config: Views, size and render options.
        renderer: A renderer to share (left open by :meth:`close`); a private one otherwise.
    """

    def __init__(self, config: ObservationConfig, renderer: SnapshotRenderer | None = None) -> None:
        self.config = config
        self._own = renderer is None
        self.renderer = renderer or SnapshotRenderer(shadows=config.shadows)

    def images(self, loop: SimLoop) -> dict[str, NDArray[np.uint8]]:
        """The configured views of the loop's current state."""
        cfg = self.config
        if not cfg.views:
            return {}
        return render_scene(loop.scene, cfg.views, cfg.size, cfg.labels, self.renderer)

    def observe(
        self, loop: SimLoop, instruction: str, step: ArmStep | None = None, step_index: int = 0
    ) -> VlaObservation:
        """The full observation of the loop's current state."""
        return VlaObservation(
            images=self.images(loop),
            proprio=read_proprioception(loop),
            instruction=instruction,
            step=step,
            step_index=step_index,
            time_s=loop.time,
        )

    def close(self) -> None:
        """Free the GL resources of a private renderer (it re-creates them if used again)."""
        if self._own:
            self.renderer.close()
