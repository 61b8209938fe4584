"""Oracle ceiling (SPEC §7): every GT plan must succeed in the simulator.

CI replays seed 0 of all 60 tasks; seeds 1-9 are ``slow`` (``pytest -m slow``). Tasks the executor
cannot finish yet are listed in ``KNOWN_FAILURES`` with the reason observed and run as
non-strict xfails, so the list is the open work of issue 4 and every other task is asserted.
"""

from __future__ import annotations

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes.generate import make_episode
from vlm_bench.executor import execute_plan

KNOWN_FAILURES = {  # task -> reason observed at seed 0 (benchmarks/oracle_sweep.py)
    "color_matched_sorting": "step 2: black_plate is out of reach",
    "cross_category_transfer": "step 1: meat_can is out of reach",
    "cross_color_sorting": "step 1: grasp of black_mug failed",
    "drawer_interaction": "step 8: top_drawer is out of reach",
    "function_detergent": "step 3: cleanser slipped from the gripper",
    "material_tin": "step 1: grasp of meat_can failed",
    "negation_constraint": "step 1: grasp of white_box failed",
    "store_and_close": "goal not met: inside(rubiks_cube, top_drawer)",
    "synonym_cup_dish": "step 1: grasp of red_mug failed",
    "tall_object_cleanser": "goal not met: inside(cleanser, blue_basket)",
    "tool_manipulation_mug": "step 3: white_plate is out of reach",
    "tower_stacking": "step 1: grasp of rubiks_cube failed",
    "variant_banana_in_bowl": "goal not met: inside(banana, blue_bowl)",
    "variant_chocolate_box": "step 1: grasp of chocolate_box failed",
    "variant_green_nut": "goal not met: inside(green_nut, yellow_basket)",
    "verb_drop": "step 1: grasp of banana failed",
}

TASKS = [t.id for t in all_tasks()]


def _cases(seeds: range) -> list[object]:
    return [
        pytest.param(task, seed, marks=pytest.mark.xfail(reason=KNOWN_FAILURES[task]))
        if task in KNOWN_FAILURES
        else pytest.param(task, seed)
        for seed in seeds
        for task in TASKS
    ]


def _replay(task: str, seed: int) -> None:
    episode = make_episode(task, seed)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert all(result.goals)
    assert result.scores is not None and result.scores.s_task == 100.0


@pytest.mark.parametrize(("task", "seed"), _cases(range(1)))
def test_gt_plan_succeeds_seed0(task: str, seed: int) -> None:
    _replay(task, seed)


@pytest.mark.slow
@pytest.mark.parametrize(("task", "seed"), _cases(range(1, 10)))
def test_gt_plan_succeeds_seeds_1_to_9(task: str, seed: int) -> None:
    _replay(task, seed)
