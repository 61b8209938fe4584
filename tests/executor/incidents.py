"""The scenes of past executor incidents, frozen as they were materialised when each was seen
(commit 357ab69, before the UAV's start altitude varied; ``tower_stacking:8`` at 87fa08c,
benchmark version 3), so a regression test keeps executing the scene that showed the problem
whatever the episode generator draws today."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

from vlm_bench.types.episode import Episode

_FILE = Path(__file__).with_name("incident_episodes.json")


@cache
def _all() -> dict[str, dict[str, object]]:
    data: dict[str, dict[str, object]] = json.loads(_FILE.read_text(encoding="utf-8"))
    return data


def incident_episode(task: str, seed: int) -> Episode:
    """The frozen episode of ``task`` and ``seed``."""
    return Episode.model_validate(_all()[f"{task}:{seed}"])
