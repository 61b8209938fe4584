"""Executor settings and results; the models live in :mod:`vlm_bench.types.execution`."""

from vlm_bench.types.execution import (
    ArmTrace,
    ExecutionResult,
    ExecutionSummary,
    ExecutorConfig,
    FlightConfig,
    StepOutcome,
    StepStatus,
    VlaMetricConfig,
    VlaScores,
)

__all__ = [
    "ArmTrace",
    "ExecutionResult",
    "ExecutionSummary",
    "ExecutorConfig",
    "FlightConfig",
    "StepOutcome",
    "StepStatus",
    "VlaMetricConfig",
    "VlaScores",
]
