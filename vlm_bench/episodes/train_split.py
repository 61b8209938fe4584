"""The train and test splits (docs/training.md#splits): seeds 0-9 are the test set (the committed,
reviewed GT under ``ground_truth/episodes/``); seeds from :data:`FIRST_TRAIN_SEED` on are the
train set, drawn on demand by the same generator (:func:`~vlm_bench.episodes.make_episode`:
layouts, table heights, UAV starts, GT plans) and never committed.

Distinct seeds draw distinct random numbers, but a train episode could still land on a test
episode's scene by chance. :func:`repeat_of` says when it does: the same task, every table of
the same height, every object within :attr:`RepeatTolerance.object_m` of its place (and its
heading within :attr:`RepeatTolerance.object_deg`) and the UAV start within
:attr:`RepeatTolerance.start_m` and :attr:`RepeatTolerance.start_deg`. Training exports leave
such an episode out (:func:`train_episodes`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from functools import cache

from vlm_bench.catalog.gt_episodes import MATERIALISED_SEEDS
from vlm_bench.episodes.committed import get_episode
from vlm_bench.episodes.generate import make_episode
from vlm_bench.errors import ConfigError
from vlm_bench.rules import wrap_deg
from vlm_bench.types.episode import Episode

TEST_SEEDS: range = MATERIALISED_SEEDS
"""The test set's seeds: the committed GT every benchmark run evaluates."""

FIRST_TRAIN_SEED = TEST_SEEDS.stop
"""The first train seed; every seed from it on is a train seed."""


def is_test_seed(seed: int) -> bool:
    """True for a seed of the test set."""
    return seed in TEST_SEEDS


def test_seeds_in(seeds: Iterable[int]) -> list[int]:
    """The seeds of ``seeds`` that belong to the test set, sorted."""
    return sorted(s for s in set(seeds) if is_test_seed(s))


@dataclass(frozen=True)
class RepeatTolerance:
    """How close a train episode must come to a test episode to count as a repeat of it."""

    object_m: float = 0.02
    """Largest horizontal displacement of any object (m); the layout jitter is ±0.03 m."""
    object_deg: float = 5.0
    """Largest heading difference of any object (deg); the jitter is ±20 deg."""
    start_m: float = 0.10
    """Largest distance between the UAV starts (m, in 3-D)."""
    start_deg: float = 10.0
    """Largest difference between the UAV start headings (deg)."""


TOLERANCE = RepeatTolerance()
"""The tolerance the splits are checked with (docs/training.md#splits)."""


@dataclass(frozen=True)
class Closeness:
    """How far one episode's scene lies from another's of the same task."""

    tables_equal: bool
    """Every object is built as the same kind (a table at the same height)."""
    object_m: float
    """Largest horizontal displacement of an object (m)."""
    object_deg: float
    """Largest heading difference of an object (deg)."""
    start_m: float
    """Distance between the UAV starts (m)."""
    start_deg: float
    """Difference between the UAV start headings (deg)."""

    def ratio(self, tolerance: RepeatTolerance = TOLERANCE) -> float:
        """The largest of each distance over its tolerance (≤ 1: within every tolerance);
        infinite where the tables differ."""
        if not self.tables_equal:
            return math.inf
        return max(
            self.object_m / tolerance.object_m,
            self.object_deg / tolerance.object_deg,
            self.start_m / tolerance.start_m,
            self.start_deg / tolerance.start_deg,
        )


def closeness(a: Episode, b: Episode) -> Closeness:
    """How far episode ``b``'s scene lies from ``a``'s (the same task: the same object ids)."""
    if a.task_id != b.task_id:
        raise ConfigError(f"episodes of different tasks: {a.task_id!r} and {b.task_id!r}")
    others = {o.id: o for o in b.objects}
    kinds = all(others[o.id].kind == o.kind for o in a.objects)
    shift = max(math.dist(o.pos[:2], others[o.id].pos[:2]) for o in a.objects)
    turn = max(abs(wrap_deg(o.yaw_deg - others[o.id].yaw_deg)) for o in a.objects)
    return Closeness(
        tables_equal=kinds,
        object_m=shift,
        object_deg=turn,
        start_m=math.dist(a.uav_start.pos, b.uav_start.pos),
        start_deg=abs(wrap_deg(a.uav_start.yaw_deg - b.uav_start.yaw_deg)),
    )


@cache
def test_episodes(task_id: str) -> tuple[Episode, ...]:
    """The test episodes of a task (seeds 0-9, as committed)."""
    return tuple(get_episode(task_id, seed) for seed in TEST_SEEDS)


def nearest_test(episode: Episode) -> tuple[int, Closeness]:
    """The test seed of ``episode``'s task whose scene comes closest to it, and how close."""
    ranked = [(closeness(t, episode), t.seed) for t in test_episodes(episode.task_id)]
    near, seed = min(ranked, key=lambda pair: (pair[0].ratio(), pair[1]))
    return seed, near


def repeat_of(episode: Episode, tolerance: RepeatTolerance = TOLERANCE) -> int | None:
    """The test seed whose episode ``episode`` repeats within ``tolerance``, or None."""
    for test in test_episodes(episode.task_id):
        if test.seed != episode.seed and closeness(test, episode).ratio(tolerance) <= 1.0:
            return test.seed
    return None


def train_episode(task_id: str, seed: int) -> Episode:
    """The episode of a train seed, drawn by the generator.

    Raises:
        ConfigError: ``seed`` is a test seed.
    """
    if is_test_seed(seed):
        raise ConfigError(
            f"seed {seed} is a test seed (test seeds: {TEST_SEEDS.start}-{TEST_SEEDS.stop - 1}); "
            f"train seeds start at {FIRST_TRAIN_SEED}"
        )
    return make_episode(task_id, seed)


@dataclass(frozen=True)
class SplitEpisode:
    """An episode a training export may use, or the test episode it repeats."""

    episode: Episode
    repeats: int | None
    """The test seed it repeats (it is left out), or None."""


def train_episodes(
    task_id: str, seeds: Iterable[int], *, allow_test_seeds: bool = False
) -> Iterator[SplitEpisode]:
    """The episodes of ``seeds`` in order, each with the test seed it repeats (if any).

    With ``allow_test_seeds`` a test seed gives its committed episode (``repeats`` None);
    without, a test seed raises :class:`~vlm_bench.errors.ConfigError`.
    """
    for seed in seeds:
        if is_test_seed(seed) and allow_test_seeds:
            yield SplitEpisode(get_episode(task_id, seed), None)
            continue
        episode = train_episode(task_id, seed)
        yield SplitEpisode(episode, repeat_of(episode))
