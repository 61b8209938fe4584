"""Skill executor (SPEC §7): replays validated plans in the simulator and checks goals."""

from vlm_bench.executor.executor import execute_plan, next_arm_step, run_move, target_ids
from vlm_bench.executor.goals import check_goal, check_goals
from vlm_bench.executor.hierarchical import Policy, grasped_object, policy_skills
from vlm_bench.executor.loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.references import StepReferences
from vlm_bench.executor.skills import default_skills
from vlm_bench.executor.types import (
    ExecutionResult,
    ExecutorConfig,
    FlightConfig,
    StepOutcome,
    StepStatus,
)
from vlm_bench.executor.vla_action import VlaAction, apply_action
from vlm_bench.executor.vla_metrics import vla_scores
from vlm_bench.executor.vla_observation import ObservationConfig, Proprioception, VlaObservation

__all__ = [
    "ExecutionResult",
    "ExecutorConfig",
    "FlightConfig",
    "ObservationConfig",
    "Policy",
    "Proprioception",
    "SimLoop",
    "SimulatorUnstable",
    "StepOutcome",
    "StepReferences",
    "StepStatus",
    "VlaAction",
    "VlaObservation",
    "apply_action",
    "check_goal",
    "check_goals",
    "default_skills",
    "execute_plan",
    "grasped_object",
    "next_arm_step",
    "policy_skills",
    "run_move",
    "target_ids",
    "vla_scores",
]
