"""Train seeds (10 and up) are drawn by the generator and never repeat a test episode (seeds
0-9, committed): the repeat check finds a near-copy of a test scene and passes a drawn one."""

from __future__ import annotations

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import get_episode, make_episode
from vlm_bench.episodes.train_split import (
    FIRST_TRAIN_SEED,
    TEST_SEEDS,
    TOLERANCE,
    closeness,
    is_test_seed,
    nearest_test,
    repeat_of,
    train_episode,
    train_episodes,
)
from vlm_bench.errors import ConfigError
from vlm_bench.types.episode import Episode, UavPose

TASK = "standard_pick_place"


def _moved(episode: Episode, seed: int, dx: float = 0.0, dyaw: float = 0.0) -> Episode:
    """``episode`` as if drawn for ``seed``, its UAV start moved ``dx`` m and turned ``dyaw``."""
    x, y, z = episode.uav_start.pos
    start = UavPose(pos=(x + dx, y, z), yaw_deg=episode.uav_start.yaw_deg + dyaw)
    return episode.model_copy(update={"seed": seed, "uav_start": start})


def test_seeds_0_to_9_are_the_test_set_and_train_seeds_follow() -> None:
    assert list(TEST_SEEDS) == list(range(10)) and FIRST_TRAIN_SEED == 10
    assert is_test_seed(9) and not is_test_seed(10)
    with pytest.raises(ConfigError, match=r"seed 3 is a test seed.*train seeds start at 10"):
        train_episode(TASK, 3)


def test_a_train_episode_is_the_generators_draw() -> None:
    assert train_episode(TASK, 12) == make_episode(TASK, 12)


def test_a_near_copy_of_a_test_scene_is_a_repeat_and_a_moved_start_is_not() -> None:
    test = get_episode(TASK, 4)
    assert closeness(test, test).ratio() == 0.0
    assert repeat_of(_moved(test, 50, dx=0.9 * TOLERANCE.start_m)) == 4
    assert repeat_of(_moved(test, 50, dyaw=0.9 * TOLERANCE.start_deg)) == 4
    assert repeat_of(_moved(test, 50, dx=1.1 * TOLERANCE.start_m)) is None
    assert repeat_of(_moved(test, 50, dyaw=1.1 * TOLERANCE.start_deg)) is None
    objects = list(test.objects)
    cube = next(i for i, o in enumerate(objects) if o.id == "gray_cube")
    x, y, z = objects[cube].pos
    objects[cube] = objects[cube].model_copy(update={"pos": (x, y + 1.1 * TOLERANCE.object_m, z)})
    assert repeat_of(_moved(test, 50).model_copy(update={"objects": tuple(objects)})) is None


def test_tables_of_another_height_never_repeat() -> None:
    test = next(
        e
        for e in (get_episode("place_on_flat_surface", s) for s in TEST_SEEDS)
        if any(o.kind.endswith("table") for o in e.objects)
    )
    objects = tuple(
        o.model_copy(update={"kind": "high_table" if o.kind != "high_table" else "low_table"})
        if o.kind.endswith("table")
        else o
        for o in test.objects
    )
    near = closeness(test, _moved(test, 50).model_copy(update={"objects": objects}))
    assert not near.tables_equal and near.ratio() == float("inf")


def test_train_episodes_flag_a_repeat_and_refuse_test_seeds(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    copy = _moved(get_episode(TASK, 7), 11)
    monkeypatch.setattr("vlm_bench.episodes.train_split.make_episode", lambda t, s: copy)
    (split,) = train_episodes(TASK, [11])
    assert split.repeats == 7
    with pytest.raises(ConfigError, match="test seed"):
        list(train_episodes(TASK, [2]))
    (allowed,) = train_episodes(TASK, [2], allow_test_seeds=True)
    assert allowed.episode == get_episode(TASK, 2) and allowed.repeats is None


@pytest.mark.parametrize(("task", "seed"), [(TASK, 12), ("drawer_interaction", 13)])
def test_drawn_train_episodes_repeat_no_test_episode(task: str, seed: int) -> None:
    episode = train_episode(task, seed)
    assert repeat_of(episode) is None
    _, near = nearest_test(episode)
    assert near.ratio() > 1.0


@pytest.mark.slow
def test_no_train_episode_of_seeds_10_to_19_repeats_a_test_episode() -> None:
    """Every task: 600 train episodes, as many as the test set (the benchmark script
    ``benchmarks/train_test_distribution.py`` checks 10-109 and prints the distributions)."""
    repeats = [
        (task.id, seed)
        for task in all_tasks()
        for seed in range(FIRST_TRAIN_SEED, FIRST_TRAIN_SEED + 10)
        if repeat_of(train_episode(task.id, seed)) is not None
    ]
    assert repeats == []
