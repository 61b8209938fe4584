"""Executor configuration and results (SPEC §7): per-step outcomes and the run's summary."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from vlm_bench.types.episode import UavPose
from vlm_bench.types.world import Frozen

StepStatus = Literal["ok", "failed", "skipped"]


class FlightConfig(Frozen):
    """How UAV ``move`` steps are flown."""

    speed: float = Field(
        default=0.5, gt=0, le=0.5, description="Cruise speed of the setpoint (m/s)."
    )
    accel: float = Field(default=0.5, gt=0, description="Setpoint acceleration (m/s²).")
    settle_tol: float = Field(
        default=0.01, gt=0, description="Position error that ends a move (m)."
    )
    settle_speed: float = Field(default=0.02, gt=0, description="Speed that ends a move (m/s).")
    settle_min_s: float = Field(default=0.3, ge=0, description="Hold time after the path (s).")
    settle_max_s: float = Field(default=4.0, gt=0, description="Longest hold after the path (s).")
    stow_s: float = Field(default=1.5, gt=0, description="Duration of the arm's stow motion (s).")


class ExecutorConfig(Frozen):
    """Executor settings; the defaults are the benchmark's."""

    flight: FlightConfig = Field(default_factory=FlightConfig)
    max_speed_unstable: float = Field(
        default=50.0, gt=0, description="Any dof speed above this marks the simulator unstable."
    )


class StepOutcome(Frozen):
    """What happened to one plan step."""

    index: int = Field(ge=0, description="Step index in the plan (0-based).")
    status: StepStatus = Field(description="ok, failed, or skipped (after an earlier failure).")
    reason: str | None = Field(default=None, description="Why it failed or was skipped.")
    duration_s: float = Field(default=0.0, ge=0, description="Simulated time the step took (s).")
    collisions: tuple[str, ...] = Field(
        default=(), description="Non-robot geoms the robot touched during the step."
    )


class ExecutionResult(Frozen):
    """The outcome of replaying one plan."""

    steps: tuple[StepOutcome, ...] = Field(description="One outcome per plan step.")
    exec_success: bool = Field(description="Every step succeeded.")
    n_steps_done: int = Field(ge=0, description="Steps that finished with status ok.")
    failure_reason: str | None = Field(default=None, description="Reason of the first failure.")
    final_uav_pose: UavPose = Field(description="UAV pose at the end of execution.")
    sim_time_s: float = Field(ge=0, description="Simulated time (s).")
    wall_time_s: float = Field(ge=0, description="Wall-clock time (s).")
