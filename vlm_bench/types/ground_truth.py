"""Materialised ground truth files (``ground_truth/episodes/<suite>/<task_id>.json``)."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from vlm_bench.types.base import Frozen
from vlm_bench.types.episode import Episode


class MaterialisedTask(Frozen):
    """The committed, reviewable GT of one task for a range of seeds."""

    task_id: str
    gt_plans: dict[str, list[dict[str, Any]]] = Field(
        description="Seed → GT plan in the paper's JSON format (for reviewers)."
    )
    episodes: tuple[Episode, ...] = Field(description="The full episodes, one per seed.")
