"""Episodes as committed: seeds 0-9 come from ``ground_truth/episodes/`` (the reviewed GT; the
drift test keeps it equal to :func:`~vlm_bench.episodes.make_episode`'s), other seeds are drawn.

Drawing an episode judges many candidate layouts (reach, clearances, view legibility); reading
the committed one is what a run, a rescore or an execution needs.
"""

from __future__ import annotations

from functools import cache

from vlm_bench.catalog.gt_episodes import load_materialised, materialised_path
from vlm_bench.catalog.tasks import get_task
from vlm_bench.episodes.generate import make_episode
from vlm_bench.types.episode import Episode
from vlm_bench.types.task import TaskSpec


@cache
def _committed(task_id: str) -> dict[int, Episode]:
    task = get_task(task_id)
    if not materialised_path(task).is_file():
        return {}
    return {ep.seed: ep for ep in load_materialised(task).episodes}


def get_episode(task: TaskSpec | str, seed: int) -> Episode:
    """The committed episode of ``task`` (a spec or its id) and ``seed``, or a freshly drawn
    one."""
    task_id = task if isinstance(task, str) else task.id
    if isinstance(seed, int) and not isinstance(seed, bool):
        found = _committed(task_id).get(seed)
        if found is not None:
            return found
    return make_episode(task, seed)
