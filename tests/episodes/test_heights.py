"""Heights that vary: the UAV starts below, at or above the first working altitude, so the first
segment's ``up``/``down`` changes between seeds and cannot be known from the task alone."""

from __future__ import annotations

from collections import Counter

import pytest

from vlm_bench.backends.blind_planner import segments
from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes.generate import START_ALTITUDE, altitude_bands, vertical_start
from vlm_bench.rules.approach import VERTICAL_MARGIN
from vlm_bench.types.geometry import APPROACH


@pytest.fixture(scope="module")
def stored() -> dict[str, list]:  # type: ignore[type-arg]
    return {t.id: list(load_materialised(t).episodes) for t in all_tasks()}


def test_start_altitude_sides_cycle_over_seeds() -> None:
    for task in all_tasks():
        sides = Counter(vertical_start(task.id, seed) for seed in range(9))
        assert sides == {-1: 3, 0: 3, 1: 3}, task.id


@pytest.mark.parametrize("working", [0.98, 1.2, 1.5, 1.75, 2.0])
def test_altitude_bands_keep_the_vertical_margin(working: float) -> None:
    lo, hi = START_ALTITUDE
    for side, (a, b) in altitude_bands(working).items():
        assert lo <= a <= b <= hi
        for z in (a, (a + b) / 2, b):
            dz = abs(working - z)
            assert abs(dz - APPROACH.vertical_threshold) >= VERTICAL_MARGIN - 1e-9, (side, z)
            assert (dz > APPROACH.vertical_threshold) == (side != 0), (side, z)


def test_at_least_40_tasks_have_two_vertical_patterns(stored: dict) -> None:  # type: ignore[type-arg]
    """The issue's goal (benchmarks/move_patterns.py prints the count and the patterns)."""
    varied = 0
    for episodes in stored.values():
        patterns = {
            tuple(tuple(d for d in seg if not d.is_horizontal) for seg in segments(ep.gt_plan))
            for ep in episodes
        }
        varied += len(patterns) >= 2
    assert varied >= 40, varied


def test_start_altitudes_span_the_range(stored: dict) -> None:  # type: ignore[type-arg]
    heights = [ep.uav_start.pos[2] for eps in stored.values() for ep in eps]
    lo, hi = START_ALTITUDE
    assert all(lo <= z <= hi for z in heights)
    assert min(heights) < 1.25 and max(heights) > 2.0


def test_first_segments_climb_descend_or_stay_in_every_third_or_so(stored: dict) -> None:  # type: ignore[type-arg]
    """No vertical choice of the first segment dominates: a blind planner cannot know it."""
    firsts = Counter(
        next((d for d in segments(ep.gt_plan)[0] if not d.is_horizontal), None)
        for eps in stored.values()
        for ep in eps
    )
    assert all(0.2 <= n / 600 <= 0.5 for n in firsts.values()), firsts
