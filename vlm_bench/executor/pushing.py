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
from numpy.typing import NDArray

from vlm_bench.catalog.world import object_kind
from vlm_bench.executor.arm import IK_OK, Arm, Reach
from vlm_bench.executor.ik import TOP_DOWN_SEED, top_down_rotation
from vlm_bench.executor.loop import ArmSkill, SimLoop
from vlm_bench.executor.motion import hold_with_gripper, joint_move
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep

Vec = NDArray[np.float64]
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

    q_pre: Vec
    q_down: Vec
    rot: Vec
    shift: Vec
    start: Vec
    end: Vec
    q_end: Vec | None
    """The posture at the stroke's end (by the arm alone), ``None``: the UAV carries the hand."""


@dataclass(frozen=True)
class PushPath:
    """A straight push: unit direction (horizontal) and the object's travel (m)."""

    direction: Vec
    travel: float


def _half_extent(lo: Vec, hi: Vec, direction: Vec) -> float:
    """Half the box's horizontal extent along ``direction``."""
    half = (hi[:2] - lo[:2]) / 2
    return float(abs(direction[0]) * half[0] + abs(direction[1]) * half[1])


def _ray_box_entry(origin: Vec, direction: Vec, lo: Vec, hi: Vec) -> float | None:
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

    def __init__(self, loop: SimLoop, arm: Arm | None = None) -> None:
        self.loop = loop
        self.arm = arm or Arm(loop)

    def _bounds(self, name: str) -> tuple[Vec, Vec]:
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

    def _contact_points(self, obj: str, path: PushPath) -> tuple[Vec, Vec]:
        """TCP positions where the push starts (behind the object) and ends."""
        lo, hi = self._bounds(obj)
        centre = (lo + hi) / 2
        height = float(lo[2]) + min(0.035, max(0.02, (hi[2] - lo[2]) / 2))
        back = _half_extent(lo, hi, path.direction) + BEHIND
        start = np.array([*(centre[:2] - path.direction * back), height])
        end = start + np.append(path.direction * (path.travel + BEHIND - 0.01), 0.0)
        return start, end

    def _assists(self, start: Vec, end: Vec) -> list[Vec]:
        """UAV moves to try: none, then backing away from the push's midpoint until it lies
        ``WORK_RADIUS`` from the arm base, or back along the push by up to ``MAX_BACK``; then
        the same 6 cm lower."""
        away = self.arm.back_off((start + end) / 2, WORK_RADIUS, WORK_RADIUS)
        back = -(end - start)[:2] / max(float(np.linalg.norm(end - start)), 1e-9)
        shifts = [np.zeros(3)] if away is None else [np.zeros(3), away]
        shifts += [np.append(back * d, 0.0) for d in (0.1, MAX_BACK)]
        return shifts + [s + np.array([0.0, 0.0, -0.06]) for s in shifts]

    def _plan(self, obj: str, path: PushPath) -> PushPlan | None:
        """How to push along ``path``: by the arm where it reaches the whole stroke, else by
        the UAV carrying the arm's start posture along (the first feasible start). The way
        down to the start must be clear (from the stowed arm, a sweep across the table
        knocked the cube away before the push began); failing that, the others in turn."""
        start, end = self._contact_points(obj, path)
        heading = math.atan2(path.direction[1], path.direction[0])
        rotations = [top_down_rotation(heading + k * math.pi / 2) for k in range(4)]
        ignore = self.arm.body_geoms(obj)
        blocked: list[Reach] = []

        def clear_ways() -> Iterator[Reach]:  # planned one UAV move at a time, as needed
            for shift in self._assists(start, end):
                sol = self.arm.plan(
                    start,
                    np.array([0.0, 0.0, ABOVE]),
                    rotations,
                    ignore,
                    c.GRIPPER_CLOSED,
                    np.asarray(TOP_DOWN_SEED),
                    assist=(shift,),
                    line=DESCENT,
                )
                if sol is not None and sol.hits:
                    blocked.append(sol)
                elif sol is not None:
                    yield sol

        carried: PushPlan | None = None
        for ways in (clear_ways(), blocked):  # ``blocked`` is complete once the first is done
            for sol in ways:
                plan, stroke = self._stroke_plan(sol, start, end, ignore)
                if plan is not None:
                    return plan
                carried = carried or stroke
            if carried is not None:
                return carried
        return None

    def _stroke_plan(
        self, sol: Reach, start: Vec, end: Vec, ignore: set[int]
    ) -> tuple[PushPlan | None, PushPlan | None]:
        """From a planned way down to the push's ``start``: the push by the arm alone where
        IK follows the stroke's line to ``end`` touching nothing but the object, else ``None``
        and the push with the UAV carrying the start posture along, where that start is clear
        (planned from the end alone, the arm lost the line halfway and the UAV, carrying the
        rest, slid the hand past the box)."""
        data, ik, arm, shift = self.loop.data, self.arm.ik, self.arm, sol.shift
        q_pre, q_down, rot = sol.q_start, sol.q_end, sol.rotation
        q_end, res = arm.solve_any(end, rot, q_down, shift)
        if res <= IK_OK and not ik.collisions(data, q_end, ignore, c.GRIPPER_CLOSED, shift):
            way = arm.line_path(q_down, start, end, rot, q_end, shift, _stroke_seconds(start, end))
            if way is not None and not arm.hits_at(way, ignore, c.GRIPPER_CLOSED, shift):
                return PushPlan(q_pre, q_down, rot, shift, start, end, way[-1]), None
        moved = shift + (end - start)
        if not ik.collisions(data, q_down, ignore, c.GRIPPER_CLOSED, moved):
            return None, PushPlan(q_pre, q_down, rot, shift, start, end, None)
        return None, None

    def push(self, episode: Episode, step: ArmStep) -> str | None:
        """Push ``step.object`` next to ``step.target``, or off its support without one;
        ``None`` on success, else the reason."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return f"unknown object {obj!r}"
        if step.target is not None and step.target not in kinds:
            return f"unknown object {step.target!r}"
        if not object_kind(kinds[obj]).movable:
            return f"{obj} cannot be pushed"
        if loop.held is not None:
            return f"cannot push while holding {loop.held}"
        paths = [self.towards(obj, step.target)] if step.target else self.off_edges(episode, obj)
        if not paths:
            return f"no clear path to push {obj} off its support"
        for path in paths:
            if (plan := self._plan(obj, path)) is not None:
                break
        else:
            return f"{obj} is out of reach"
        before = np.array(loop.data.body(obj).xpos)
        ok = self._stroke(plan)
        if not ok:
            return f"{obj} is out of reach"
        moved = float(np.dot(loop.data.body(obj).xpos[:2] - before[:2], path.direction))
        if moved < MIN_MOVE * path.travel:
            return f"{obj} moved {moved:.2f} m of {path.travel:.2f} m"
        return None

    def _stroke(self, plan: PushPlan) -> bool:
        """Run the push, then lift the hand, stow the arm and fly the UAV back; ``False`` where
        the hand could not come down behind the object."""
        loop, arm = self.loop, self.arm
        arm.shift_base(plan.shift)
        joint_move(loop, plan.q_pre, 2.5, c.GRIPPER_CLOSED)
        above = plan.start + np.array([0.0, 0.0, ABOVE])
        ok = arm.line(above, plan.start, plan.rot, DESCENT, c.GRIPPER_CLOSED, plan.q_down)
        stroke = plan.end - plan.start
        unit = stroke / max(float(np.linalg.norm(stroke)), 1e-9)
        back = plan.shift
        if ok:
            if plan.q_end is not None:  # the box may hold the hand back...
                seconds = _stroke_seconds(plan.start, plan.end)
                arm.line(plan.start, plan.end, plan.rot, seconds, c.GRIPPER_CLOSED, plan.q_end)
            rest = float(np.dot(plan.end - arm.tcp()[0], unit))
            if rest > 0.01:  # ...then the UAV carries the hand the rest of the way
                arm.carry(unit * rest, SPEED)
                back = back + unit * rest
        hold_with_gripper(loop, 0.3, c.GRIPPER_CLOSED)
        tcp, _ = arm.tcp()
        arm.line(tcp, tcp - unit * 0.03 + np.array([0.0, 0.0, ABOVE]), plan.rot, 1.0, 0.0)
        arm.shift_base(-back - arm.stow())
        return ok


def _stroke_seconds(start: Vec, end: Vec) -> float:
    """How long the stroke from ``start`` to ``end`` takes at :data:`SPEED` (at least 1.5 s)."""
    return max(1.5, float(np.linalg.norm(end - start)) / SPEED)


def push_skills(loop: SimLoop, arm: Arm | None = None) -> dict[str, ArmSkill]:
    """``push`` bound to one loop."""
    pusher = Pusher(loop, arm)
    return {"push": lambda _loop, episode, step: pusher.push(episode, step)}
