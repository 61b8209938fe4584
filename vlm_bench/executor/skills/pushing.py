"""Scripted non-prehensile ``push`` with IK and contact physics.

The closed hand, pointing down, is lowered behind the object (opposite the push direction) to a
few centimetres above the object's bottom and moved along a straight line, so the fingers slide
the object over its support. With a ``target`` the object is pushed towards the target's centre
until its leading face is ``PUSH_GAP`` from the target's footprint; without one it is pushed off
its support, over the closest edge the arm can reach along a path clear of other objects.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.motion.arm_core import IK_OK
from vlm_bench.executor.motion.arm_planner import Reach
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.ik import TOP_DOWN_SEED, top_down_rotation
from vlm_bench.executor.motion.joint_moves import hold_with_gripper, joint_move
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.sim.constants import GRIPPER_CLOSED
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep

PUSH_GAP = 0.03  # m left between the pushed object's leading face and the target's footprint
BEHIND = 0.035  # m between the object's trailing face and the TCP where the push starts
ABOVE = 0.10  # m: the hand comes down to the push height from this far above it
PAST_EDGE = 0.03  # m the object's trailing face is pushed beyond its support's edge
SPEED = 0.10  # m/s along the push
MIN_MOVE = 0.5  # fraction of the commanded travel the object must move for a push to count
CLEARANCE = 0.01  # m kept between the pushed object's swept box and other objects
WORK_RADIUS = 0.40  # m, horizontal: the UAV may back away until the push's midpoint is this far
MAX_BACK = 0.2  # m the UAV may back away along the push
DESCENT = 1.2  # s: the hand's straight way down to the push height


@dataclass(frozen=True)
class PushPlan:
    """A feasible push: pre-push posture above the start, the posture at the start at the
    end of the planned way down, hand orientation, the UAV's move before it, the TCP's start
    and end, and the posture at the end."""

    q_pre: FloatArray
    q_down: FloatArray
    rot: FloatArray
    shift: BaseMove
    start: FloatArray
    end: FloatArray
    q_end: FloatArray | None
    """The posture at the stroke's end (by the arm alone), ``None``: the UAV carries the hand."""


@dataclass(frozen=True)
class PushPath:
    """A straight push: unit direction (horizontal) and the object's travel (m)."""

    direction: FloatArray
    travel: float


def _half_extent(lo: FloatArray, hi: FloatArray, direction: FloatArray) -> float:
    """Half the box's horizontal extent along ``direction``."""
    half = (hi[:2] - lo[:2]) / 2
    return float(abs(direction[0]) * half[0] + abs(direction[1]) * half[1])


def _ray_box_entry(
    origin: FloatArray, direction: FloatArray, lo: FloatArray, hi: FloatArray
) -> float | None:
    """Distance along the horizontal ray to where it enters the box [lo, hi] (x, y), or
    ``None`` if it misses; 0 if it starts inside."""
    t0, t1 = 0.0, math.inf
    for k in range(2):
        if abs(direction[k]) < 1e-9:
            if not lo[k] <= origin[k] <= hi[k]:
                return None
            continue
        a = (lo[k] - origin[k]) / direction[k]
        b = (hi[k] - origin[k]) / direction[k]
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    return t0 if t0 <= t1 else None


class Pusher:
    """``push`` for one scene."""

    def __init__(self, hand: Hand) -> None:
        self.hand = hand
        self.loop = hand.loop

    def _bounds(self, name: str) -> tuple[FloatArray, FloatArray]:
        return object_bounds(self.loop.model, self.loop.data, name, solid_only=True)

    def towards(self, obj: str, target: str) -> PushPath:
        """Push ``obj`` at ``target``'s centre, stopping ``PUSH_GAP`` short of its footprint."""
        lo, hi = self._bounds(obj)
        tlo, thi = self._bounds(target)
        centre, goal = (lo + hi) / 2, (tlo + thi) / 2
        offset = goal[:2] - centre[:2]
        direction = offset / max(float(np.linalg.norm(offset)), 1e-9)
        grow = _half_extent(lo, hi, direction) + PUSH_GAP
        entry = _ray_box_entry(centre[:2], direction, tlo[:2] - grow, thi[:2] + grow)
        return PushPath(direction, max(0.0, entry or 0.0))

    def off_edges(self, episode: Episode, obj: str) -> list[PushPath]:
        """Pushes that take ``obj`` over each edge of its support, shortest first, leaving out
        those whose swept path meets another object."""
        support = next(o.on for o in episode.objects if o.id == obj)
        if support == "floor":
            return []
        lo, hi = self._bounds(obj)
        slo, shi = self._bounds(support)
        centre = (lo + hi) / 2
        paths = []
        for direction in (
            np.array(v, dtype=np.float64) for v in ((1, 0), (-1, 0), (0, 1), (0, -1))
        ):
            k = 0 if direction[0] else 1
            edge = shi[k] if direction[k] > 0 else slo[k]
            to_edge = abs(edge - centre[k])
            paths.append(PushPath(direction, to_edge + _half_extent(lo, hi, direction) + PAST_EDGE))
        paths.sort(key=lambda p: p.travel)
        return [p for p in paths if self._clear(episode, obj, support, p)]

    def _clear(self, episode: Episode, obj: str, support: str, path: PushPath) -> bool:
        """Whether the object's box, swept along ``path``, stays clear of other objects."""
        lo, hi = self._bounds(obj)
        shift = np.append(path.direction * path.travel, 0.0)
        slo, shi = np.minimum(lo, lo + shift), np.maximum(hi, hi + shift)
        for other in episode.objects:
            if other.id in (obj, support):
                continue
            olo, ohi = self._bounds(other.id)
            overlap = np.all(slo[:2] < ohi[:2] + CLEARANCE) and np.all(
                shi[:2] > olo[:2] - CLEARANCE
            )
            if overlap and slo[2] < ohi[2] and shi[2] > olo[2]:
                return False
        return True

    def _contact_points(self, obj: str, path: PushPath) -> tuple[FloatArray, FloatArray]:
        """TCP positions where the push starts (behind the object) and ends."""
        lo, hi = self._bounds(obj)
        centre = (lo + hi) / 2
        height = float(lo[2]) + min(0.035, max(0.02, (hi[2] - lo[2]) / 2))
        back = _half_extent(lo, hi, path.direction) + BEHIND
        start = np.array([*(centre[:2] - path.direction * back), height])
        end = start + np.append(path.direction * (path.travel + BEHIND - 0.01), 0.0)
        return start, end

    def _assists(self, start: FloatArray, end: FloatArray) -> list[BaseMove]:
        """UAV moves to try: none, then backing away from the push's midpoint until it lies
        ``WORK_RADIUS`` from the arm base, or back along the push by up to ``MAX_BACK``; then
        the same 6 cm lower; then 6 cm higher (a hand that must come down over the far side of
        a low UAV)."""
        away = self.hand.planner.back_off((start + end) / 2, WORK_RADIUS, WORK_RADIUS)
        back = -(end - start)[:2] / max(float(np.linalg.norm(end - start)), 1e-9)
        shifts = [np.zeros(3)] if away is None else [np.zeros(3), away]
        shifts += [np.append(back * d, 0.0) for d in (0.1, MAX_BACK)]
        lower = [s + np.array([0.0, 0.0, -0.06]) for s in shifts]
        higher = [s + np.array([0.0, 0.0, 0.06]) for s in shifts]
        return [BaseMove(s) for s in (*shifts, *lower, *higher)]

    def _plan(self, obj: str, path: PushPath) -> PushPlan | None:
        """How to push along ``path``: by the arm where it reaches the whole stroke, else by
        the UAV carrying the arm's start posture along (the first feasible start). The way
        down to the start must be clear (a sweep into the object moves it before the push
        begins); failing that, the others in turn."""
        start, end = self._contact_points(obj, path)
        heading = math.atan2(path.direction[1], path.direction[0])
        rotations = [top_down_rotation(heading + k * math.pi / 2) for k in range(4)]
        ignore = self.hand.body_geoms(obj)

        def ways(clear: bool) -> Iterator[Reach]:  # planned one UAV move at a time, as needed
            for shift in self._assists(start, end):
                sol = self.hand.planner.plan(
                    start,
                    np.array([0.0, 0.0, ABOVE]),
                    rotations,
                    ignore,
                    GRIPPER_CLOSED,
                    np.asarray(TOP_DOWN_SEED),
                    assist=(shift,),
                    line=DESCENT,
                    max_hits=0 if clear else math.inf,
                )
                if sol is not None and (clear or sol.hits):
                    yield sol

        carried: PushPlan | None = None
        # The clear ways first; the blocked ones (each the best of its UAV move) only where
        # none of those gives a push: counting their contacts is most of the search.
        for ways_in in (ways(clear=True), ways(clear=False)):
            for sol in ways_in:
                plan, stroke = self._stroke_plan(sol, start, end, ignore)
                if plan is not None:
                    return plan
                carried = carried or stroke
            if carried is not None:
                return carried
        return None

    def _stroke_plan(
        self, sol: Reach, start: FloatArray, end: FloatArray, ignore: set[int]
    ) -> tuple[PushPlan | None, PushPlan | None]:
        """From a planned way down to the push's ``start``: the push by the arm alone where
        IK follows the stroke's line to ``end`` touching nothing but the object, else ``None``
        and the push with the UAV carrying the start posture along, where that start is clear
        (the whole line is checked, not its end alone: an arm that loses the line halfway
        leaves the UAV to carry a hand that is no longer behind the object)."""
        core, lines, shift = self.hand.core, self.hand.lines, sol.shift
        q_pre, q_down, rot = sol.q_start, sol.q_end, sol.rotation
        query = CollisionQuery.of(ignore, GRIPPER_CLOSED, shift)
        q_end, res = core.solve_any(end, rot, q_down, shift)
        if res <= IK_OK and not core.collisions(q_end, query):
            seconds = _stroke_seconds(start, end)
            way = lines.line_path(q_down, start, end, rot, q_end, shift, seconds)
            if way is not None and not core.hits_at(way, query, limit=0):
                return PushPlan(q_pre, q_down, rot, shift, start, end, way[-1]), None
        moved = shift.plus(end - start)
        if not core.collisions(q_down, CollisionQuery.of(ignore, GRIPPER_CLOSED, moved)):
            return None, PushPlan(q_pre, q_down, rot, shift, start, end, None)
        return None, None

    def push(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Push ``step.object`` next to ``step.target``, or off its support without one;
        ``None`` on success, else the reason."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {obj!r}")
        if step.target is not None and step.target not in kinds:
            return SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {step.target!r}")
        if not object_kind(kinds[obj]).movable:
            return SkillFailure(FailureCode.NOT_PUSHABLE, f"{obj} cannot be pushed")
        if loop.held is not None:
            return SkillFailure(FailureCode.BUSY_HAND, f"cannot push while holding {loop.held}")
        paths = [self.towards(obj, step.target)] if step.target else self.off_edges(episode, obj)
        if not paths:
            return SkillFailure(
                FailureCode.PUSH_BLOCKED, f"no clear path to push {obj} off its support"
            )
        for path in paths:
            if (plan := self._plan(obj, path)) is not None:
                break
        else:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{obj} is out of reach")
        before = np.array(loop.data.body(obj).xpos)
        ok = self._stroke(plan)
        if not ok:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{obj} is out of reach")
        moved = float(np.dot(loop.data.body(obj).xpos[:2] - before[:2], path.direction))
        if moved < MIN_MOVE * path.travel:
            return SkillFailure(
                FailureCode.PUSH_SHORT, f"{obj} moved {moved:.2f} m of {path.travel:.2f} m"
            )
        return None

    def _stroke(self, plan: PushPlan) -> bool:
        """Run the push, then lift the hand, stow the arm and fly the UAV back; ``False`` where
        the hand could not come down behind the object."""
        loop, hand = self.loop, self.hand
        hand.shift_base(plan.shift)
        joint_move(loop, plan.q_pre, 2.5, GRIPPER_CLOSED)
        above = plan.start + np.array([0.0, 0.0, ABOVE])
        ok = hand.lines.line(above, plan.start, plan.rot, DESCENT, GRIPPER_CLOSED, plan.q_down)
        stroke = plan.end - plan.start
        unit = stroke / max(float(np.linalg.norm(stroke)), 1e-9)
        back = plan.shift
        if ok:
            if plan.q_end is not None:  # the box may hold the hand back...
                seconds = _stroke_seconds(plan.start, plan.end)
                hand.lines.line(plan.start, plan.end, plan.rot, seconds, GRIPPER_CLOSED, plan.q_end)
            rest = float(np.dot(plan.end - hand.tcp()[0], unit))
            if rest > 0.01:  # ...then the UAV carries the hand the rest of the way
                hand.carry(unit * rest, SPEED)
                back = back.plus(unit * rest)
        hold_with_gripper(loop, 0.3, GRIPPER_CLOSED)
        tcp, _ = hand.tcp()
        hand.lines.line(tcp, tcp - unit * 0.03 + np.array([0.0, 0.0, ABOVE]), plan.rot, 1.0, 0.0)
        hand.shift_base(BaseMove(-back.xyz - hand.stow(), -back.yaw))
        return ok


def _stroke_seconds(start: FloatArray, end: FloatArray) -> float:
    """How long the stroke from ``start`` to ``end`` takes at :data:`SPEED` (at least 1.5 s)."""
    return max(1.5, float(np.linalg.norm(end - start)) / SPEED)


def push_skills(loop: SimLoop, hand: Hand | None = None) -> dict[str, Skill]:
    """``push`` bound to one loop."""
    pusher = Pusher(hand or Hand(loop))
    return {"push": pusher.push}
