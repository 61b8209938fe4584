"""Write and check the committed GT (``ground_truth/episodes``)."""

from __future__ import annotations

import json
from collections.abc import Iterable

from vlm_bench.catalog.gt_episodes import MATERIALISED_SEEDS, materialised_path
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes.generate import make_episode
from vlm_bench.types.ground_truth import MaterialisedTask
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.task import TaskSpec


def materialise(task: TaskSpec, seeds: Iterable[int] = MATERIALISED_SEEDS) -> MaterialisedTask:
    """Generate the episodes of one task for ``seeds``."""
    episodes = tuple(make_episode(task, s) for s in seeds)
    return MaterialisedTask(
        task_id=task.id,
        gt_plans={str(e.seed): plan_to_json(e.gt_plan) for e in episodes},
        episodes=episodes,
    )


def to_text(item: MaterialisedTask) -> str:
    """Stable, reviewable JSON text."""
    return json.dumps(item.model_dump(mode="json"), indent=1) + "\n"


def write_ground_truth() -> list[str]:
    """Regenerate every task's file; returns the paths written."""
    written = []
    for task in all_tasks():
        path = materialised_path(task)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(to_text(materialise(task)), encoding="utf-8")
        written.append(str(path))
    return written


def drifted_tasks() -> list[str]:
    """Task ids whose committed GT differs from a fresh generation (or is missing)."""
    out = []
    for task in all_tasks():
        path = materialised_path(task)
        fresh = to_text(materialise(task))
        if not path.is_file() or path.read_text(encoding="utf-8") != fresh:
            out.append(task.id)
    return out
