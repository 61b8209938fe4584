"""A live episode continues one simulation across plans; its state is described as it stands;
perturbations fire as seeded."""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.live_state import episode_now, render_now
from vlm_bench.executor.perturbations import Perturber
from vlm_bench.executor.perturbations.bump import BUMP_RANGE
from vlm_bench.prompting.builder import scene_text
from vlm_bench.rules import parse_scene
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.plan import ArmStep, Direction, UavStep

TASK = "standard_pick_place"
HOP = [UavStep(direction=Direction.UP, distance=0.2)]


def _same(a: object, b: object) -> bool:
    drop = {"wall_time_s"}
    return a.model_dump(exclude=drop) == b.model_dump(exclude=drop)  # type: ignore[attr-defined]


def test_a_second_plan_continues_where_the_first_left() -> None:
    episode = get_episode(TASK, 0)
    live = LiveEpisode(episode)
    first = live.execute(HOP)
    z1 = first.final_uav_pose.pos[2]
    second = live.execute(HOP)
    assert second.final_uav_pose.pos[2] == pytest.approx(z1 + 0.2, abs=0.02)
    assert second.sim_time_s > first.sim_time_s  # the episode's clock runs on
    assert _same(first, execute_plan(episode, HOP))  # round 0 is the one-shot execution


def test_the_state_now_moves_objects_relative_to_the_uav() -> None:
    episode = get_episode(TASK, 0)
    live = LiveEpisode(episode)
    before = {e.id: e for e in parse_scene(scene_text(episode_now(live), []))}
    live.execute(HOP)
    now = episode_now(live)
    after = {e.id: e for e in parse_scene(scene_text(now, []))}
    assert now.uav_start.yaw_deg == episode.uav_start.yaw_deg  # the moves' frame
    for name, entry in before.items():
        assert after[name].point[2] == pytest.approx(entry.point[2] - 0.2, abs=0.03)
        assert after[name].floor_height == pytest.approx(entry.floor_height, abs=0.015)
    images = render_now(live, now, ("uav", "overhead"), 32, labels=True)
    assert set(images) == {"uav", "overhead"} and all(
        p.startswith(b"\x89PNG") for p in images.values()
    )


def test_a_bump_displaces_the_object_on_its_support_as_seeded() -> None:
    episode = get_episode(TASK, 0)
    shifts = []
    for _ in range(2):
        live = LiveEpisode(episode)
        before = np.array(live.loop.data.body("gray_cube").xpos)
        perturber = Perturber(PerturbConfig(bump=1.0), episode)
        perturber.before_arm_step(live.loop, 1, ArmStep(object="gray_cube", skill="pick"))
        live.loop.hold(0.5)
        (event,) = perturber.events
        moved = np.array(live.loop.data.body("gray_cube").xpos) - before
        assert event.kind == "bump" and event.object == "gray_cube"
        assert BUMP_RANGE[0] - 1e-6 <= float(np.hypot(*event.shift)) <= BUMP_RANGE[1] + 1e-6
        assert moved[:2] == pytest.approx(event.shift, abs=0.01)
        assert abs(moved[2]) < 0.01  # still on the table
        shifts.append(event.shift)
    assert shifts[0] == shifts[1]  # seeded per episode


def test_no_bump_at_zero_probability_and_fixed_objects_stay() -> None:
    episode = get_episode(TASK, 0)
    live = LiveEpisode(episode)
    perturber = Perturber(PerturbConfig(bump=1.0), episode)
    perturber.before_arm_step(live.loop, 0, ArmStep(object="table", skill="push"))
    assert perturber.events == []
    quiet = Perturber(PerturbConfig(slip=0.5), episode)
    quiet.before_arm_step(live.loop, 0, ArmStep(object="gray_cube", skill="pick"))
    assert quiet.events == []


def test_a_slip_drops_the_held_object_once_and_place_fails() -> None:
    episode = get_episode("place_on_flat_surface", 0)  # a flight with the object in hand
    live = LiveEpisode(episode, ExecutorConfig(perturb=PerturbConfig(slip=1.0)))
    plan = [*episode.gt_plan[:-1], UavStep(direction=Direction.UP, distance=0.1)]
    result = live.execute([*plan, episode.gt_plan[-1]])  # two flights with it "in hand"
    (event,) = result.perturbations or ()
    assert event.kind == "slip" and result.failure_code == "slipped"
    assert live.held is None
    again = live.execute([UavStep(direction=Direction.UP, distance=0.1)])
    assert again.perturbations == ()  # nothing in the hand: nothing more to drop
