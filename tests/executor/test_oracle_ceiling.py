"""Oracle ceiling (docs/design.md#oracle-ceiling): every GT plan must succeed in the simulator.

The default suite executes seed 0 of :data:`CI_TASKS`, which between them hold every skill of
the GT plans and every suite; the other tasks' seed 0 and seeds 1-9 are ``slow`` (``pytest -m
slow``: 600 executions, several minutes on a 2-core machine). Episodes the
executor cannot finish yet are listed in ``KNOWN_FAILURES`` (task, seed) with the reason observed
and run as non-strict xfails, so the list is the open work of issue 4 and every other episode is
asserted.
"""

from __future__ import annotations

from collections.abc import Sequence

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep

KNOWN_FAILURES: dict[tuple[str, int], str] = {}  # (task, seed) -> reason observed

TASKS = [t.id for t in all_tasks()]
CI_TASKS = (
    "standard_pick_place",
    "spatial_ref_middle_drawer",
    "preposition_by_dont",
    "hybrid_interaction_stove",
    "store_and_close",
)
"""Seed-0 executions in the default suite: every GT skill (pick, place, pull, push, rotate, close)
and every suite in five episodes (checked by :func:`test_ci_tasks_hold_every_skill_and_suite`)."""


def _cases(seeds: range, tasks: Sequence[str] = TASKS) -> list[object]:
    return [
        pytest.param(task, seed, marks=pytest.mark.xfail(reason=KNOWN_FAILURES[task, seed]))
        if (task, seed) in KNOWN_FAILURES
        else pytest.param(task, seed)
        for seed in seeds
        for task in tasks
    ]


def _execute(task: str, seed: int) -> None:
    episode = get_episode(task, seed)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert all(result.goals)
    assert result.scores is not None and result.scores.s_task == 100.0


def test_ci_tasks_hold_every_skill_and_suite() -> None:
    episodes = [get_episode(task, 0) for task in TASKS]
    ci = [e for e in episodes if e.task_id in CI_TASKS]
    assert len(ci) == len(CI_TASKS)
    assert {e.suite for e in ci} == {e.suite for e in episodes}

    def skills(chosen: list[Episode]) -> set[str]:
        return {s.skill for e in chosen for s in e.gt_plan if isinstance(s, ArmStep)}

    assert skills(ci) == skills(episodes)


@pytest.mark.smoke  # every skill and suite executes in the default suite
@pytest.mark.parametrize(("task", "seed"), _cases(range(1), CI_TASKS))
def test_gt_plan_succeeds_seed0(task: str, seed: int) -> None:
    _execute(task, seed)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("task", "seed"), _cases(range(1), [t for t in TASKS if t not in CI_TASKS])
)
def test_gt_plan_succeeds_seed0_other_tasks(task: str, seed: int) -> None:
    _execute(task, seed)


@pytest.mark.slow
@pytest.mark.parametrize(("task", "seed"), _cases(range(1, 10)))
def test_gt_plan_succeeds_seeds_1_to_9(task: str, seed: int) -> None:
    _execute(task, seed)
