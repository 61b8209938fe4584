"""Plan execution in the simulator (docs/design.md#execution-metrics): settings, per-step
outcomes, the run's summary.

These models cross the executor → runner → storage boundary (a record carries an
:class:`ExecutionSummary`), so they live in the types layer.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Literal

from pydantic import Field, SerializerFunctionWrapHandler, model_serializer

from vlm_bench.types.base import FiniteFrozen, Frozen, omit_none
from vlm_bench.types.closed_loop import PerturbConfig, PerturbEvent
from vlm_bench.types.episode import UavPose

StepStatus = Literal["ok", "failed", "skipped"]


class FailureCode(StrEnum):
    """Why a plan step, or a whole execution, failed: one code per kind of failure reason."""

    UNKNOWN_OBJECT = "unknown_object"
    """The step names an object or part the scene does not have."""
    UNKNOWN_SKILL = "unknown_skill"
    """The executor has no skill of that name (a policy pipeline may cover fewer skills)."""
    OUT_OF_REACH = "out_of_reach"
    """No planned arm motion (with the UAV's small assists) reaches the object or release."""
    ALREADY_HOLDING = "already_holding"
    """A pick while the hand holds an object."""
    NOT_GRASPABLE = "not_graspable"
    """A pick of an object the catalogue marks as not graspable."""
    GRASP_FAILED = "grasp_failed"
    """The fingers closed but do not both touch the object (or it did not rise), or a handle."""
    SLIPPED = "slipped"
    """The held object left the fingers before its release."""
    NOTHING_HELD = "nothing_held"
    """A place with an empty hand."""
    NOT_PUSHABLE = "not_pushable"
    """A push of an object the catalogue marks as fixed."""
    PUSH_BLOCKED = "push_blocked"
    """No push off the object's support keeps its swept path clear of other objects."""
    PUSH_SHORT = "push_short"
    """The pushed object moved less than half the commanded travel."""
    ARTICULATION_SHORT = "articulation_short"
    """A drawer or knob did not reach the opening, closing or turn the skill requires."""
    WRONG_PART = "wrong_part"
    """An articulation skill on an object without that part, or on a part of another kind."""
    BUSY_HAND = "busy_hand"
    """A push or articulation while the hand holds an object."""
    POLICY_TIMEOUT = "policy_timeout"
    """A low-level policy did not end its step within its control-step budget."""
    SKILL_FAILED = "skill_failed"
    """A user-supplied skill failed with a free-text reason and no code."""
    EARLIER_FAILURE = "earlier_failure"
    """The step was skipped: an earlier step failed."""
    GOAL_NOT_MET = "goal_not_met"
    """Every step succeeded but a task goal does not hold after settling."""
    SIMULATOR_UNSTABLE = "simulator_unstable"
    """The simulation blew up (non-finite or absurdly fast state)."""
    EXECUTOR_CRASH = "executor_crash"
    """The executor raised (or its worker died); the runner records it and carries on."""
    SIM_BUDGET = "sim_budget"
    """The execution used up its simulated-time budget (:meth:`ExecutorConfig.sim_budget_s`)."""


@dataclass(frozen=True)
class SkillFailure:
    """A failed skill: its code and the human-readable detail recorded as its reason."""

    code: FailureCode
    detail: str

    def __str__(self) -> str:
        return self.detail


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


class VlaMetricConfig(Frozen):
    """Constants of the paper's VLA metrics (Appendix A.3).

    The paper fixes the UAV range (0.5–0.8 m, peak 0.65 m) and the safety kernel (full at
    ≤ 0.01 m, σ = 2/3 m, 0 at ≥ 2 m); the paper leaves λ, σ_pos, β, σ_arm and d_thresh open,
    so the values here are ours and documented in docs/design.md#execution-metrics.
    """

    pos_mu: float = Field(default=0.65, description="Ideal arm-base distance to the object (m).")
    pos_min: float = Field(default=0.50, description="Shortest feasible distance d_min (m).")
    pos_max: float = Field(default=0.80, description="Longest feasible distance d_max (m).")
    pos_sigma: float = Field(default=0.10, gt=0, description="σ of the positioning kernel (m).")
    lambda_act: float = Field(default=0.8, ge=0, le=1, description="λ when interaction attempted.")
    lambda_hov: float = Field(default=0.4, ge=0, le=1, description="λ when only hovering.")
    arm_beta: float = Field(default=0.3, ge=0, le=1, description="β, weight of S_ori in S_arm.")
    arm_sigma: float = Field(default=0.05, gt=0, description="σ_arm of the TCP kernel (m).")
    arm_thresh: float = Field(default=0.20, gt=0, description="d_thresh of the TCP kernel (m).")
    ori_max_tilt_deg: float = Field(
        default=15.0, gt=0, description="TCP axis deviation that breaks S_ori (deg)."
    )
    safe_deadband: float = Field(
        default=0.01, ge=0, description="Total displacement still scored 100 (m)."
    )
    safe_sigma: float = Field(default=2.0 / 3.0, gt=0, description="σ_safe (m).")
    safe_limit: float = Field(default=2.0, gt=0, description="Δ_limit: 0 at or beyond (m).")
    w_pos: float = Field(default=0.25, ge=0, description="Weight of S_pos in the VLA total.")
    w_arm: float = Field(default=0.25, ge=0, description="Weight of S_arm.")
    w_safe: float = Field(default=0.10, ge=0, description="Weight of S_safe.")
    w_task: float = Field(default=0.40, ge=0, description="Weight of S_task.")


def episode_noise_seed(task_id: str, seed: int) -> int:
    """Seed of an episode's gusts: stable across runs and machines, and shared by both
    instruction variants (so their executions face the same wind)."""
    digest = hashlib.sha256(f"uav-noise|{task_id}|{seed}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


class ExecutorConfig(Frozen):
    """Executor settings; the defaults are the benchmark's.

    A run builds one from its config (:meth:`RunConfig.executor_config
    <vlm_bench.types.run.RunConfig.executor_config>`) and every job it sends to a worker
    carries it; it holds no per-episode value (the gust seed defaults to the episode's).
    """

    flight: FlightConfig = Field(default_factory=FlightConfig)
    metrics: VlaMetricConfig = Field(default_factory=VlaMetricConfig)
    max_speed_unstable: float = Field(
        default=50.0, gt=0, description="Any dof speed above this marks the simulator unstable."
    )
    settle_s: float = Field(
        default=1.0, ge=0, description="Simulated time the scene settles before goals (s)."
    )
    uav_noise: float = Field(
        default=0.0,
        ge=0,
        description="Gust force std on the UAV (N); 0 = calm (the paper's UAV Disturb.).",
    )
    noise_seed: int | None = Field(
        default=None,
        description="Seed of the gust process; None: the episode's (episode_noise_seed).",
    )
    perturb: PerturbConfig | None = Field(
        default=None, description="Seeded perturbations to fire (``--perturb``); None: none."
    )
    budget_base_s: float = Field(
        default=60.0, gt=0, description="Simulated time every execution may use (s)."
    )
    budget_per_step_s: float = Field(
        default=40.0, ge=0, description="Simulated time each plan step adds to the budget (s)."
    )

    def gust_seed(self, task_id: str, seed: int) -> int:
        """The gust seed of episode ``task_id``/``seed``: :attr:`noise_seed` where set."""
        return episode_noise_seed(task_id, seed) if self.noise_seed is None else self.noise_seed

    def sim_budget_s(self, n_steps: int) -> float:
        """The simulated time an execution of ``n_steps`` steps may use before settling (s).

        ``budget_base_s + budget_per_step_s × n_steps``. GT steps take up to 26 s of simulated
        time (docs/decisions.md), and a policy-driven ARM step ends at 30 s
        (:data:`~vlm_bench.vla.hierarchical.DEFAULT_MAX_STEPS`), so no plan that finishes comes
        near it, while an execution that cannot finish ends in :attr:`FailureCode.SIM_BUDGET`.
        """
        return self.budget_base_s + self.budget_per_step_s * n_steps


class ArmTrace(FiniteFrozen):
    """What the metrics need from one ARM step (measured, not planned)."""

    object: str = Field(description="The step's object id.")
    known: bool = Field(description="The object exists in the scene.")
    base_distance: float | None = Field(
        default=None, description="Arm base to the object's reference point at step start (m)."
    )
    ee_distance: float | None = Field(
        default=None, description="Closest TCP approach to the object's interaction point (m)."
    )
    tilt_deg: float | None = Field(
        default=None, description="TCP axis deviation from the skill's approach axis at contact."
    )
    attempted: bool = Field(default=False, description="The arm moved towards the object.")


class StepOutcome(FiniteFrozen):
    """What happened to one plan step."""

    index: int = Field(ge=0, description="Step index in the plan (0-based).")
    agent: Literal["UAV", "ARM"] = Field(description="Which agent the step commands.")
    status: StepStatus = Field(description="ok, failed, or skipped (after an earlier failure).")
    reason: str | None = Field(default=None, description="Why it failed or was skipped.")
    failure_code: FailureCode | None = Field(
        default=None, description="The kind of failure, where ``reason`` is set."
    )
    duration_s: float = Field(default=0.0, ge=0, description="Simulated time the step took (s).")
    collisions: tuple[str, ...] = Field(
        default=(), description="Non-robot geoms the robot touched during the step."
    )
    arm: ArmTrace | None = Field(default=None, description="ARM steps: measurements.")


class VlaScores(FiniteFrozen):
    """The paper's VLA metrics, each in [0, 100]."""

    s_pos: float = Field(ge=0, le=100, description="Base positioning accuracy.")
    s_arm: float = Field(ge=0, le=100, description="Manipulator efficacy.")
    s_safe: float = Field(ge=0, le=100, description="Environmental disturbance safety.")
    s_task: float = Field(ge=0, le=100, description="Sub-goal completion 100·done/K.")
    total: float = Field(ge=0, le=100, description="Weighted total.")


class ExecutionResult(FiniteFrozen):
    """The outcome of executing one plan."""

    steps: tuple[StepOutcome, ...] = Field(description="One outcome per plan step.")
    steps_ok: bool = Field(description="Every step succeeded.")
    exec_success: bool = Field(description="Every step succeeded and every goal holds.")
    n_steps_done: int = Field(ge=0, description="Steps that finished with status ok.")
    failure_reason: str | None = Field(default=None, description="Reason of the first failure.")
    failure_code: FailureCode | None = Field(
        default=None, description="The kind of the first failure, where it is set."
    )
    goals: tuple[bool, ...] = Field(default=(), description="Each task goal, after settling.")
    displacement: dict[str, float] = Field(
        default_factory=dict, description="Non-target movable objects' displacement (m)."
    )
    uav_collisions: tuple[str, ...] = Field(
        default=(), description="Non-robot geoms the robot touched, whole run."
    )
    scores: VlaScores | None = Field(default=None, description="VLA metrics.")
    final_uav_pose: UavPose = Field(description="UAV pose at the end of execution.")
    sim_time_s: float = Field(ge=0, description="Simulated time (s).")
    wall_time_s: float = Field(ge=0, description="Wall-clock time (s).")
    perturbations: tuple[PerturbEvent, ...] | None = Field(
        default=None, description="Perturbations that fired (None: the run perturbs nothing)."
    )

    @property
    def s_task(self) -> float:
        """Sub-goal completion in percent (0 with no goals)."""
        return 100.0 * sum(self.goals) / len(self.goals) if self.goals else 0.0


class ExecutionSummary(FiniteFrozen):
    """The part of an :class:`ExecutionResult` stored in a run record."""

    exec_success: bool
    steps_ok: bool
    n_steps_done: int = Field(ge=0)
    failure_reason: str | None = None
    failure_code: FailureCode | None = None
    goals: tuple[bool, ...] = ()
    s_task: float = Field(ge=0, le=100)
    scores: VlaScores | None = None
    uav_collisions: tuple[str, ...] = ()
    displacement_total: float = Field(default=0.0, ge=0)
    sim_time_s: float = Field(ge=0)
    wall_time_s: float = Field(ge=0)
    perturbations: tuple[PerturbEvent, ...] | None = None
    """Perturbations that fired (None, and left out of the JSON, where the run perturbs
    nothing)."""

    @model_serializer(mode="wrap")
    def _omit_unperturbed(self, handler: SerializerFunctionWrapHandler) -> Any:
        return omit_none(handler(self), ("perturbations",))

    @classmethod
    def of(cls, result: ExecutionResult) -> ExecutionSummary:
        """The stored summary of ``result``."""
        return cls(
            exec_success=result.exec_success,
            steps_ok=result.steps_ok,
            n_steps_done=result.n_steps_done,
            failure_reason=result.failure_reason,
            failure_code=result.failure_code,
            goals=result.goals,
            s_task=result.s_task,
            scores=result.scores,
            uav_collisions=result.uav_collisions,
            displacement_total=sum(result.displacement.values()),
            sim_time_s=result.sim_time_s,
            wall_time_s=result.wall_time_s,
            perturbations=result.perturbations,
        )


class ExecutionOptions(Frozen):
    """Where a run executes its plans (not part of its configuration: outcomes do not depend
    on it)."""

    workers: int | None = Field(
        default=None,
        ge=0,
        description="Executions at once: worker processes, or Ray tasks; 0 = inline, in the run's "
        "process, no overlap with generation; None = the machine's cores.",
    )
    backend: Literal["process", "ray"] = Field(
        default="process", description="Worker processes of this machine, or a Ray cluster."
    )
    ray_address: str | None = Field(
        default=None, description="Ray cluster address (ray backend); None = a local cluster."
    )
    stall_s: float = Field(
        default=600.0,
        gt=0,
        description="With executions in flight and none finishing for this long (s), those in "
        "flight are given up as lost (a resume runs them again). 3.5 times the longest execution "
        "a plan can make (860 s simulated: 172 s at a real-time factor of 5), so a machine 3.5 "
        "times slower still finishes it; only a hung worker or a lost node reaches it (a lost "
        "Ray node is announced within a minute).",
    )
