"""Looking for clear plans before counting contacts changes no choice: a pick's grasp and a
push's way down are the ones the rules pick when every search counts every contact (the first
grasp point with a clear descent, else the first the hand reaches; the clear ways of a push
before its blocked ones), checked on whole episodes against those rules written out in full, and
the pick's rule on a planner stand-in (no GT pick needs a second grasp point)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from tests.executor.motion.test_arm_planner_pruning import _same
from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.motion.arm_planner import ArmPlanner, Reach
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.ik import TOP_DOWN_SEED, top_down_rotation
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills import grasping, pushing
from vlm_bench.executor.skills.grasp_points import grasp_points
from vlm_bench.executor.skills.grasping import GRASP_DESCENT, GRASP_TURN_ROOM, PRE_GRASP, Picker
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.pushing import ABOVE, DESCENT, Pusher, PushPath, PushPlan
from vlm_bench.sim.constants import GRIPPER_CLOSED, GRIPPER_OPEN
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.scene import build_scene
from vlm_bench.types.base import FloatArray
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.world import ObjectKind


def _full(planner: ArmPlanner, *args: Any, **kwargs: Any) -> Reach | None:
    """:meth:`ArmPlanner.plan` for every contact count (no ``max_hits``)."""
    return ArmPlanner.plan(planner, *args, **{**kwargs, "max_hits": math.inf})


def _grasp_in_full(picker: Picker, obj: str, kind: ObjectKind) -> tuple[Reach, FloatArray] | None:
    """The pick's rule with full searches: grasp points in order, the first clear descent,
    else the first point with any."""
    loop = picker.loop
    lo, hi = object_bounds(loop.model, loop.data, obj, solid_only=True)
    body = loop.data.body(obj)
    rot = body.xmat.reshape(3, 3)
    yaw = math.atan2(rot[1, 0], rot[0, 0])
    candidates = grasp_points(kind, np.array(body.xpos), yaw, lo, hi, np.array(body.xipos))
    fallback = None
    for cand in candidates:
        point = (
            picker.on_section(obj, cand.point, cand.rotations[0])
            if cand.centre_across
            else cand.point
        )
        sol = _full(
            picker.hand.planner,
            point,
            np.array([0.0, 0.0, PRE_GRASP]),
            cand.rotations,
            picker.hand.body_geoms(obj),
            GRIPPER_OPEN,
            np.asarray(TOP_DOWN_SEED),
            line=GRASP_DESCENT,
            turn_room=GRASP_TURN_ROOM,
        )
        if sol is None:
            continue
        if sol.hits == 0:
            return sol, point
        fallback = fallback or (sol, point)
    return fallback


def _push_in_full(pusher: Pusher, obj: str, path: PushPath) -> PushPlan | None:
    """The push's rule with full searches: UAV moves in order, each searched once; the ways
    down that touch nothing first, then those that touch."""
    start, end = pusher._contact_points(obj, path)
    heading = math.atan2(path.direction[1], path.direction[0])
    rotations = [top_down_rotation(heading + k * math.pi / 2) for k in range(4)]
    ignore = pusher.hand.body_geoms(obj)
    sols = [
        _full(
            pusher.hand.planner,
            start,
            np.array([0.0, 0.0, ABOVE]),
            rotations,
            ignore,
            GRIPPER_CLOSED,
            np.asarray(TOP_DOWN_SEED),
            assist=(shift,),
            line=DESCENT,
        )
        for shift in pusher._assists(start, end)
    ]
    carried = None
    for ways in (
        [s for s in sols if s is not None and not s.hits],
        [s for s in sols if s is not None and s.hits],
    ):
        for sol in ways:
            plan, stroke = pusher._stroke_plan(sol, start, end, ignore)
            if plan is not None:
                return plan
            carried = carried or stroke
        if carried is not None:
            return carried
    return None


def _same_push(a: PushPlan | None, b: PushPlan | None) -> bool:
    if a is None or b is None:
        return a is b
    arrays = ("q_pre", "q_down", "rot", "start", "end")
    return (
        a.shift.key() == b.shift.key()
        and all(np.array_equal(getattr(a, f), getattr(b, f)) for f in arrays)
        and (a.q_end is None) == (b.q_end is None)
        and (a.q_end is None or b.q_end is None or np.array_equal(a.q_end, b.q_end))
    )


@pytest.mark.parametrize(
    ("task", "seed"), [("variant_chocolate_box", 3), ("multi_object_sorting", 3)]
)
def test_a_pick_chooses_the_grasp_the_full_searches_choose(
    monkeypatch: pytest.MonkeyPatch, task: str, seed: int
) -> None:
    plan_grasp = Picker.plan_grasp
    picks = []

    def compared(self: Picker, obj: str, kind: ObjectKind) -> tuple[Reach, FloatArray] | None:
        got = plan_grasp(self, obj, kind)
        want = _grasp_in_full(self, obj, kind)
        assert (got is None) == (want is None), obj
        if got is not None and want is not None:
            assert _same(got[0], want[0]) and np.array_equal(got[1], want[1]), obj
        picks.append(obj)
        return got

    episode = get_episode(task, seed)
    monkeypatch.setattr(grasping.Picker, "plan_grasp", compared)
    assert execute_plan(episode, episode.gt_plan).exec_success
    assert picks


@pytest.mark.parametrize(
    ("task", "seed"), [("non_prehensile_push_cube", 3), ("clear_desk_push_box", 1)]
)
def test_a_push_chooses_the_way_the_full_searches_choose(
    monkeypatch: pytest.MonkeyPatch, task: str, seed: int
) -> None:
    plan = Pusher._plan
    pushes = []

    def compared(self: Pusher, obj: str, path: PushPath) -> PushPlan | None:
        got = plan(self, obj, path)
        assert _same_push(got, _push_in_full(self, obj, path)), obj
        pushes.append(obj)
        return got

    monkeypatch.setattr(pushing.Pusher, "_plan", compared)
    episode = get_episode(task, seed)
    assert execute_plan(episode, episode.gt_plan).exec_success
    assert pushes


def test_a_pick_takes_a_later_clear_grasp_over_an_earlier_blocked_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The rule itself, on a planner stand-in: the first grasp point's best descent touches
    something and the second's is clear, so the second is taken; with no clear point, the
    first point reached is."""
    episode = get_episode("precise_insertion_mug", 1)  # a mug: grasp points round its rim
    picker = Picker(Hand(SimLoop(build_scene(episode))))
    obj = next(s.object for s in episode.gt_plan if isinstance(s, ArmStep) and s.skill == "pick")
    kind = object_kind(next(o.kind for o in episode.objects if o.id == obj))
    seen: list[bytes] = []
    clear_from = {"index": 1}

    def stand_in(self: ArmPlanner, point: FloatArray, *args: Any, **kwargs: Any) -> Reach | None:
        key = np.asarray(point).tobytes()
        if key not in seen:
            seen.append(key)
        hits = 0 if seen.index(key) >= clear_from["index"] else 2
        if hits > kwargs.get("max_hits", math.inf):
            return None
        q = np.zeros(7)
        return Reach(q, np.eye(3), BaseMove.still(), q, hits)

    monkeypatch.setattr(ArmPlanner, "plan", stand_in)
    got = picker.plan_grasp(obj, kind)
    assert len(seen) >= 2 and got is not None
    assert got[0].hits == 0 and got[1].tobytes() == seen[1]
    seen.clear()
    clear_from["index"] = 99
    got = picker.plan_grasp(obj, kind)
    assert got is not None and got[0].hits == 2 and got[1].tobytes() == seen[0]
