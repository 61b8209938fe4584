"""Read the committed, materialised episodes."""

from __future__ import annotations

from pathlib import Path

from vlm_bench.catalog.files import load_model
from vlm_bench.resources import ground_truth_dir
from vlm_bench.types.ground_truth import MaterialisedTask
from vlm_bench.types.task import TaskSpec

MATERIALISED_SEEDS = range(10)


def episodes_dir() -> Path:
    """Folder of materialised GT, one sub-folder per suite."""
    return ground_truth_dir() / "episodes"


def materialised_path(task: TaskSpec) -> Path:
    """Where a task's materialised GT lives."""
    return episodes_dir() / task.suite.value / f"{task.id}.json"


def load_materialised(task: TaskSpec) -> MaterialisedTask:
    """The committed GT of one task (validated)."""
    return load_model(materialised_path(task), MaterialisedTask)
