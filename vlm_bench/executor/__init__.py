"""Skill executor (SPEC §7): replays validated plans in the simulator and checks goals."""

from vlm_bench.executor.executor import execute_plan, next_arm_step, run_move
from vlm_bench.executor.goals import check_goal, check_goals
from vlm_bench.executor.loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.types import (
    ExecutionResult,
    ExecutorConfig,
    FlightConfig,
    StepOutcome,
    StepStatus,
)

__all__ = [
    "ExecutionResult",
    "ExecutorConfig",
    "FlightConfig",
    "SimLoop",
    "SimulatorUnstable",
    "StepOutcome",
    "StepStatus",
    "check_goal",
    "check_goals",
    "execute_plan",
    "next_arm_step",
    "run_move",
]
