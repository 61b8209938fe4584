"""Legibility from geometry (vlm_bench.sim.view_sizes) and its rendered judge (footprint)."""

from __future__ import annotations

import pytest

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks, get_task
from vlm_bench.sim.cameras import task_objects
from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_SIDE
from vlm_bench.sim.footprint import Legibility, ObjectFootprint, legibility_failures
from vlm_bench.sim.view_sizes import (
    frame_problem,
    is_small_part,
    legibility_score,
    min_pixels,
    object_pixel_sizes,
)
from vlm_bench.types.episode import Episode


def _episode(task: str, seed: int) -> Episode:
    return load_materialised(get_task(task)).episodes[seed]


def _moved_start(ep: Episode, dx: float) -> Episode:
    x, y, z = ep.uav_start.pos
    return ep.model_copy(
        update={"uav_start": ep.uav_start.model_copy(update={"pos": (x + dx, y, z)})}
    )


def test_bolts_and_nuts_are_small_parts_cubes_and_cups_are_not() -> None:
    assert is_small_part("bolt") and is_small_part("nut")
    assert not any(is_small_part(k) for k in ("cube", "rubiks_cube", "cup", "camera_module"))
    assert (min_pixels("bolt"), min_pixels("cube")) == (6, 12)


@pytest.mark.parametrize(
    ("estimate", "legible"),
    [(13.4, False), (12.2, False), (12.0, False), (14.0, True)],  # the first three rendered 11
)
def test_an_estimate_just_over_the_bound_is_not_judged_legible(
    estimate: float, legible: bool
) -> None:
    ep = _episode("deformable_object_banana", 0)
    sizes = {oid: {CAM_OVERHEAD: 40.0, CAM_SIDE: 40.0} for oid in task_objects(ep)}
    sizes["banana"] = {CAM_OVERHEAD: 7.2, CAM_SIDE: estimate}
    assert (legibility_score(ep, sizes) >= 1.0) is legible


def test_a_farther_uav_start_shrinks_every_task_object() -> None:
    ep = _episode("small_object_bolt", 7)
    near, far = object_pixel_sizes(ep), object_pixel_sizes(_moved_start(ep, 1.5))
    for oid in near:
        assert max(far[oid].values()) < max(near[oid].values()), oid
    assert legibility_score(ep, far) < legibility_score(ep, near)


def test_a_view_pushed_against_the_wall_cuts_off_the_work_area() -> None:
    ep = _episode("standard_pick_place", 0)
    assert frame_problem(ep) is None
    assert frame_problem(_moved_start(ep, 9.0)) is not None  # the room is 9 m across


def test_every_episode_records_its_task_objects_sizes_in_both_views() -> None:
    for task in all_tasks():
        for ep in load_materialised(task).episodes:
            assert set(ep.object_px) == set(task_objects(ep)), (task.id, ep.seed)
            assert all(set(v) == {CAM_OVERHEAD, CAM_SIDE} for v in ep.object_px.values())


def test_the_issue_example_is_legible_by_geometry() -> None:
    for task, seed in (("cross_color_sorting", 5),):
        ep = _episode(task, seed)
        assert legibility_score(ep, ep.object_px) >= 1.0, (task, ep.object_px)


def _fp(seen: int, edge: bool = False) -> ObjectFootprint:
    return ObjectFootprint(seen=seen, clear=seen, covered=False, long=seen, edge=edge)


@pytest.mark.parametrize(
    ("prints", "need", "whole", "expected"),
    [
        ({"overhead": _fp(8), "side": _fp(12)}, 12, True, []),  # the better view counts
        ({"overhead": _fp(8), "side": _fp(11)}, 12, True, ["cup 11px, needs 12px"]),
        ({"overhead": _fp(20, edge=True), "side": _fp(20)}, 12, True, ["cut off"]),
        ({"overhead": _fp(90, edge=True), "side": _fp(90)}, 12, False, []),  # a fixture
        ({"overhead": _fp(0), "side": _fp(30)}, 12, True, ["not in the overhead view"]),
    ],
)
def test_the_rendered_judge(
    prints: dict[str, ObjectFootprint], need: int, whole: bool, expected: list[str]
) -> None:
    row = Legibility(
        task="t",
        seed=0,
        size=448,
        arrow={"overhead": 40.0, "side": 40.0},
        objects={"cup": prints},
        need={"cup": need},
        whole=("cup",) if whole else (),
    )
    failures = legibility_failures(row)
    assert len(failures) == len(expected), failures
    for got, want in zip(failures, expected, strict=True):
        assert want in got
