"""The planner's pruning changes no plan: every reach planned in a whole episode equals the one
a search that checks every candidate in full would choose, and a search for at most ``max_hits``
contacts returns the full search's plan where it has that few, else nothing."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.motion import arm_planner
from vlm_bench.executor.motion.arm_planner import NO_PLAN, ArmPlanner, Reach, _Target
from vlm_bench.executor.motion.ik import SEED_POSTURES
from vlm_bench.executor.skills.place_descents import Descents, Drop
from vlm_bench.executor.skills.release_points import can_drop_into
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.episode import Episode


def _unpruned(
    planner: ArmPlanner,
    point: Any,
    approach: Any,
    rotations: Any,
    ignore: set[int],
    gripper: float,
    seed: Any,
    assist: Any = None,
    clearance: float = 0.0,
    line: float | None = None,
    turn_room: float = 0.0,
    max_hits: float = math.inf,
) -> Reach | None:
    """:meth:`ArmPlanner.plan` as its rules state it: every candidate (every start, repeats
    included) ranked on its whole key, with no bound to prune against."""
    now = arm_qpos(planner.loop.model, planner.loop.data)
    carried = planner.core.carried()
    target = _Target(point, approach, ignore, gripper, clearance, line, turn_room, carried)
    held = carried.geoms if carried is not None else set()
    starts = [np.asarray(seed), now, *map(np.asarray, SEED_POSTURES)]
    best, best_key = None, (float(max_hits), *NO_PLAN[1:])
    for shift in planner.assists(point) if assist is None else assist:
        turning = planner.turn_hits(shift, now, held, carried)
        for rot in rotations:
            for start in starts:
                found = planner._candidate(target, rot, start, shift, now, turning, NO_PLAN)
                if found is None:
                    continue
                reach, key = found
                if key < best_key:
                    best, best_key = reach, key
                if key[0] == 0 and key[1] == 0:
                    break
        if best is not None and best_key[0] == 0:
            return best
    return best


def _release_in_full(ways: Descents, episode: Episode, drop: Drop) -> tuple[Reach, Drop] | None:
    """The release as its rule states it: the best way down to it; where that touches and the
    object may drop in, the best way to above the rim instead if it touches less."""
    sol = ways._top_down_to(episode, drop, drop.release)
    if (sol is None or sol.hits) and can_drop_into(ways.hand, episode, drop.held, drop.dest):
        rim = drop.release.copy()
        rim[2] = drop.above[2] - 0.03
        high = ways._top_down_to(episode, drop, rim)
        if high is not None and (sol is None or high.hits < sol.hits):
            return high, Drop(drop.held, drop.dest, rim, drop.above, drop.heading, drop.ignore)
    return None if sol is None else (sol, drop)


def _same(a: Reach | None, b: Reach | None) -> bool:
    if a is None or b is None:
        return a is b
    return (
        a.hits == b.hits
        and a.shift.key() == b.shift.key()
        and all(np.array_equal(x, y) for x, y in zip(a[:2] + a[3:4], b[:2] + b[3:4], strict=True))
    )


def test_every_planned_reach_is_the_unpruned_search_s(monkeypatch: pytest.MonkeyPatch) -> None:
    """variant_chocolate_box seed 3: the release into the box is planned over every assist
    (each way down swings the held box wider than 2 rad), then the rim, for fewer contacts;
    the release chosen is the one of the full searches of both, compared."""
    plan = ArmPlanner.plan
    plan_release = Descents.plan_release
    calls = {"all": 0, "bounded": 0, "hits": 0}

    def checked(self: ArmPlanner, *args: Any, **kwargs: Any) -> Reach | None:
        got = plan(self, *args, **kwargs)
        full = _unpruned(self, *args, **{**kwargs, "max_hits": math.inf})
        bound = kwargs.get("max_hits", math.inf)
        want = full if full is None or full.hits <= bound else None
        assert _same(got, want), (args[0], bound, got, want)
        calls["all"] += 1
        calls["bounded"] += bound < math.inf
        calls["hits"] += full is not None and full.hits > 0
        return got

    def compared(self: Descents, episode: Episode, drop: Drop) -> tuple[Reach, Drop] | None:
        with monkeypatch.context() as full:
            full.setattr(arm_planner.ArmPlanner, "plan", _unpruned)
            want = _release_in_full(self, episode, drop)
        got = plan_release(self, episode, drop)
        assert (got is None) == (want is None)
        if got is not None and want is not None:
            assert _same(got[0], want[0]) and np.array_equal(got[1].release, want[1].release)
        return got

    monkeypatch.setattr(arm_planner.ArmPlanner, "plan", checked)
    monkeypatch.setattr(Descents, "plan_release", compared)
    episode = get_episode("variant_chocolate_box", 3)
    assert execute_plan(episode, episode.gt_plan).exec_success
    assert calls["bounded"] and calls["hits"], calls  # the cases the pruning is for ran
