"""The rules the prompt states reproduce the GT: through the scene text, on every episode."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.rules import (
    UavState,
    WorkPoint,
    ambiguity,
    approach_moves,
    body_bearing_deg,
    format_scene,
    parse_scene,
    plan_from_scene,
    plan_segments,
    quantise_bearing,
    scene_entries,
)
from vlm_bench.rules.approach import (
    DECISION_MARGIN,
    SECTOR_MARGIN_DEG,
    VERTICAL_MARGIN,
    altitude_error,
    horizontal_distance,
)
from vlm_bench.types.episode import Episode
from vlm_bench.types.geometry import APPROACH
from vlm_bench.types.plan import Direction

SEEDS = range(10)


@pytest.fixture(scope="module")
def episodes() -> list[Episode]:
    """The materialised episodes of seeds 0-9 (equal to ``get_episode``'s: the drift test in
    tests/episodes checks it)."""
    return [ep for t in all_tasks() for ep in load_materialised(t).episodes if ep.seed in SEEDS]


def _text(ep: Episode) -> str:
    return format_scene(scene_entries(ep), ep.uav_start.pos[2])


def test_the_scene_text_and_the_rules_give_every_gt_plan(episodes: list[Episode]) -> None:
    """The GT's UAV moves follow from the scene text (two decimals) and the prompt's rules."""
    for ep in episodes:
        entries = parse_scene(_text(ep))
        assert plan_from_scene(entries, ep.arm_steps()) == list(ep.gt_plan), (ep.task_id, ep.seed)


def test_no_gt_decision_is_near_its_threshold(episodes: list[Episode]) -> None:
    """Every reach, sector and altitude decision is clear of its threshold by the GT's margins
    (0.15 m of the reach limit, 8 deg of a sector boundary, 6 cm of the vertical threshold),
    less what the text's rounding to 1 cm can move it."""
    text_error = 0.01  # m, two coordinates rounded to 0.005 m each
    for ep in episodes:
        for segment in plan_segments(parse_scene(_text(ep)), ep.arm_steps()):
            uav, point = segment.uav, segment.point
            assert point is not None
            key = (ep.task_id, ep.seed, segment.step.object)
            dist = horizontal_distance(uav, point)
            assert abs(dist - APPROACH.reach_horizontal) >= DECISION_MARGIN - text_error, key
            dz = abs(altitude_error(uav, point))
            assert abs(dz - APPROACH.vertical_threshold) >= VERTICAL_MARGIN - text_error, key
            if dist > APPROACH.reach_horizontal:
                _, margin = quantise_bearing(body_bearing_deg(uav.xy, uav.yaw_deg, point.xy))
                slack = math.degrees(text_error / dist)
                assert margin >= SECTOR_MARGIN_DEG - slack, key


def test_scene_text_round_trips(episodes: list[Episode]) -> None:
    for ep in episodes[::7]:
        assert parse_scene(_text(ep)) == scene_entries(ep)


coord = st.floats(-3.0, 3.0, allow_nan=False).map(lambda v: round(v, 2))


@settings(max_examples=300, deadline=None)
@given(x=coord, y=coord, z=st.floats(-1.5, 1.0).map(lambda v: round(v, 2)))
def test_approach_moves_bring_the_point_into_reach_at_working_altitude(
    x: float, y: float, z: float
) -> None:
    uav = UavState(0.0, 0.0, 0.0, 0.0)
    point = WorkPoint(x, y, z, APPROACH.standoff_horizontal)
    legs = approach_moves(uav, point)
    directions = [leg.direction for leg in legs]
    horizontal = [d for d in directions if d.is_horizontal]
    assert len(horizontal) <= 1
    if Direction.UP in directions:
        assert directions[0] == Direction.UP
    if Direction.DOWN in directions:
        assert directions[-1] == Direction.DOWN
    end = legs[-1].end if legs else uav
    if ambiguity(uav, point) is None:  # clear decisions leave the point in reach at altitude
        assert (end.x - x) ** 2 + (end.y - y) ** 2 <= APPROACH.reach_horizontal**2 + 1e-9
        assert abs(APPROACH.operating_altitude(z) - end.z) <= APPROACH.vertical_threshold
