"""What a demos export records (:class:`DemoExportConfig`) and what it wrote
(:class:`DemoExportSummary`)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from pydantic import Field

from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_WRIST, CONTROL_DT
from vlm_bench.types.base import Frozen
from vlm_bench.types.task import InstructionVariant, Suite
from vlm_bench.vla.demos.variation import DemoVariation

FPS = round(1 / CONTROL_DT)
"""Frames per second of a demonstration: the control rate (20 Hz)."""
DEFAULT_VIEWS = (CAM_WRIST, CAM_OVERHEAD)
DEFAULT_SIZE = 96
SOURCE_TASK = "vlm_bench/task_id"
SOURCE_SEED = "vlm_bench/seed"
SOURCE_STEP = "vlm_bench/plan_step"
"""Episodes-table columns naming where a LeRobot episode came from: the benchmark task, the
episode seed and the GT plan step (-1: the whole execution)."""


class DemoExportConfig(Frozen):
    """What an export records."""

    tasks: tuple[str, ...] = Field(default=(), description="Task ids; () = every task (of suite).")
    suite: Suite | None = Field(default=None, description="Only this suite's tasks.")
    seeds: tuple[int, ...] = Field(description="Episode seeds (train seeds are 10 and up).")
    variant: InstructionVariant = Field(default="explicit", description="Instruction as task.")
    views: tuple[str, ...] = Field(default=DEFAULT_VIEWS, description="Cameras recorded.")
    size: int = Field(default=DEFAULT_SIZE, ge=16, le=512, description="Image side (px, even).")
    per_arm_step: bool = Field(
        default=False, description="One LeRobot episode per ARM step (task: the step's command)."
    )
    variation: DemoVariation = Field(default_factory=DemoVariation, description="Variation.")
    allow_test_seeds: bool = Field(default=False, description="Accept seeds 0-9 (test set).")


@dataclass
class DemoExportSummary:
    """What an export wrote and what it left out."""

    folder: Path
    executions: int = 0
    kept: int = 0
    episodes: int = 0
    frames: int = 0
    failures: Counter[str] = field(default_factory=Counter)
    """Left-out executions by failure code (``action_out_of_bounds`` for a replay risk)."""
