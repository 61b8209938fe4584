"""IK's stall rules: a solve gives up where its lowest residual stops falling, after 20
iterations judged on the last 10, or, for the planner's candidate solves (which have other
starts), after 12 judged on the last 6; a line's steps keep the longer rule."""

from __future__ import annotations

import sys
from typing import Any

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.motion import ik as ik_module
from vlm_bench.executor.motion.ik import (
    CANDIDATE_STALL,
    STALL,
    TOP_DOWN_SEED,
    ArmIk,
    stalled,
    top_down_rotation,
)
from vlm_bench.executor.motion.ik_qp import IkQp
from vlm_bench.executor.step_execution import episode_scene
from vlm_bench.sim import constants as c
from vlm_bench.types.execution import ExecutorConfig


@pytest.mark.parametrize("rule", [STALL, CANDIDATE_STALL])
def test_a_flat_history_stalls_just_after_the_rule_s_iterations(rule: tuple[int, int]) -> None:
    after, _ = rule
    flat = [1.0] * after
    assert not stalled(flat, rule)
    assert stalled([*flat, 1.0], rule)
    falling = [0.9**k for k in range(after + 5)]  # 10 % less each iteration: still converging
    assert not stalled(falling, rule)


def test_a_solve_that_cannot_converge_stops_where_its_rule_says(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A point 3 m below the arm: the residual flattens at once, so the candidate rule gives
    up as soon as it may; the longer rule iterates at least as long as it promises."""
    scene = episode_scene(get_episode("standard_pick_place", 0), ExecutorConfig())
    mujoco.mj_forward(scene.model, scene.data)
    ik = ArmIk(scene.model)
    far = np.array(scene.data.body(c.ARM_BASE_BODY).xpos) - np.array([0.0, 0.0, 3.0])
    calls: list[int] = []
    velocity = IkQp.velocity

    def counted(self: IkQp, *args: Any) -> Any:
        calls.append(1)
        return velocity(self, *args)

    monkeypatch.setattr(IkQp, "velocity", counted)
    iterations = {}
    for rule in (STALL, CANDIDATE_STALL):
        calls.clear()
        _, residual = ik.solve(
            scene.data, far, top_down_rotation(0.0), np.array(TOP_DOWN_SEED), stall=rule
        )
        assert residual > 1.0
        iterations[rule] = len(calls)
    assert iterations[CANDIDATE_STALL] == CANDIDATE_STALL[0]
    assert iterations[STALL] >= STALL[0]


def test_the_planner_s_candidates_take_the_shorter_rule_and_lines_the_longer(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Every solve of standard_pick_place seed 0's GT execution: the planner's candidates (from
    their start postures) under the candidate rule, a line's previewed steps under the
    longer one."""
    rules: dict[str, set[tuple[int, int]]] = {"_candidate": set(), "_preview": set()}
    solve = ik_module.ArmIk.solve

    def recorded(self: ArmIk, *args: Any, stall: tuple[int, int] = STALL, **kwargs: Any) -> Any:
        caller = sys._getframe(1).f_code.co_name
        if caller in rules:
            rules[caller].add(stall)
        return solve(self, *args, **{**kwargs, "stall": stall})

    monkeypatch.setattr(ik_module.ArmIk, "solve", recorded)
    episode = get_episode("standard_pick_place", 0)
    assert execute_plan(episode, episode.gt_plan).exec_success
    assert rules == {"_candidate": {CANDIDATE_STALL}, "_preview": {STALL}}
