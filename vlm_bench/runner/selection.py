"""Which episodes a run evaluates, in which order, and the default run folder name."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from vlm_bench.backends import operational_args
from vlm_bench.catalog.tasks import get_task, tasks_in
from vlm_bench.resources import results_dir
from vlm_bench.types.records import episode_key
from vlm_bench.types.run import RunConfig
from vlm_bench.types.task import InstructionVariant


@dataclass(frozen=True)
class EpisodeRef:
    """One episode of a run: task × seed × instruction variant."""

    task_id: str
    seed: int
    variant: InstructionVariant

    @property
    def key(self) -> str:
        """``task_id/seed/variant``, the episode's key in records and the response cache."""
        return episode_key(self.task_id, self.seed, self.variant)


def select_episodes(config: RunConfig) -> list[EpisodeRef]:
    """The run's episodes in benchmark order: task, then seed, then variant.

    Both variants of a task × seed are adjacent, so they share one scene and one set of snapshots.

    Raises:
        UnknownNameError: A task id that does not exist (lists the valid ids).
    """
    if config.tasks:
        wanted = {get_task(t).id for t in config.tasks}  # validates every id
        task_ids = [t.id for t in tasks_in(None) if t.id in wanted]
    else:
        task_ids = [t.id for t in tasks_in(config.suite)]
    return [
        EpisodeRef(task_id, seed, variant)
        for task_id in task_ids
        for seed in config.seeds
        for variant in config.instructions
    ]


def model_slug(model: str) -> str:
    """A folder-safe form of a model string: ``Qwen/Qwen2.5-VL-7B`` → ``qwen-qwen2.5-vl-7b``."""
    slug = re.sub(r"[^a-z0-9._-]+", "-", model.lower()).strip("-._")
    return slug[:60].rstrip("-._") or "model"


def default_run_dir(config: RunConfig, base: Path | None = None) -> Path:
    """``<results>/<model-slug>-<short config hash>`` (operational backend arguments left out)."""
    short = config.short_hash(operational_args(config.model))
    return (base or results_dir()) / f"{model_slug(config.model)}-{short}"
