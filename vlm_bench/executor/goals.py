"""Goal predicates on a simulated state (docs/design.md#goals), checked after the scene has settled.

Objects are measured by their solid geoms: the centre of their world bounding box and its bottom.
A target's footprint is its catalogue box (x, y) in its own yawed frame; a drawer's is the
bounding box of the drawer body (cabinets stand axis-aligned with their drawers). Thresholds
are the official evaluator's where it has one (0.20 m containment bound, 0.15 m for ``near``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.sim.constants import part_joint
from vlm_bench.sim.objects.bounds import geom_bounds, object_bounds, subtree_geoms
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.task import Goal

INSIDE_MAX_CENTRE_DIST = 0.20  # m, official evaluator's upper bound
NEAR_DIST = 0.15  # m, horizontal, object centre to target footprint
UPRIGHT_MAX_TILT_DEG = 20.0
DRAWER_OPEN = 0.30  # m
DRAWER_CLOSED = 0.02  # m
KNOB_ROTATED_DEG = 75.0
ON_GAP_ABOVE = 0.03  # m: a resting object's bottom at most this far above the support's top
ON_GAP_BELOW = 0.03  # m: ...and at most this far below it (plates, soft contacts)
FLOOR_TOL = 0.01  # m: an object inside a container sits no lower than its base minus this
INSIDE_BELOW_RIM = 0.015  # m: ...and its lowest point at least this far below the rim


@dataclass(frozen=True)
class Box:
    """An object's extent now: bounding-box centre, bottom and top (m, world)."""

    centre: FloatArray
    bottom: float
    top: float


class GoalState:
    """Read-only view of a settled scene for evaluating goals."""

    def __init__(self, episode: Episode, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.episode = episode
        self.model = model
        self.data = data
        self.objects = {o.id: o for o in episode.objects}
        self.parts = {p.id: p for p in episode.parts}

    def box(self, name: str) -> Box:
        lo, hi = object_bounds(self.model, self.data, name, solid_only=True)
        return Box(centre=(lo + hi) / 2, bottom=float(lo[2]), top=float(hi[2]))

    def surface(self, name: str) -> float:
        """Height of what rests on ``name``: its top, not counting its parts (a stove's knob
        stands 5 cm above the cooktop)."""
        obj = self.objects.get(name)
        if obj is None or not object_kind(obj.kind).parts:
            return self.box(name).top
        body = self.model.body(name).id
        tops = [
            geom_bounds(self.model, self.data, g)[1][2]
            for g in subtree_geoms(self.model, body, solid_only=True)
            if self.model.geom_bodyid[g] == body
        ]
        return float(max(tops))

    def in_footprint(self, point: FloatArray, target: str, margin: float = 0.0) -> bool:
        """Whether ``point`` lies horizontally within ``target``'s footprint (grown by margin)."""
        if target in self.parts:
            lo, hi = object_bounds(self.model, self.data, target, solid_only=True)
            return bool(
                np.all(point[:2] >= lo[:2] - margin) and np.all(point[:2] <= hi[:2] + margin)
            )
        size = object_kind(self.objects[target].kind).size
        rot = self.data.body(target).xmat.reshape(3, 3)
        local = rot.T @ (point - self.data.body(target).xpos)
        return bool(abs(local[0]) <= size[0] / 2 + margin and abs(local[1]) <= size[1] / 2 + margin)

    def joint_value(self, part: str) -> float:
        return float(self.data.qpos[self.model.joint(part_joint(part)).qposadr[0]])


def _horizontal(a: FloatArray, b: FloatArray) -> float:
    return math.hypot(float(a[0] - b[0]), float(a[1] - b[1]))


def is_inside(state: GoalState, obj: str, container: str) -> bool:
    """Object centre within the container's footprint (and ≤ 0.20 m from the container's),
    its lowest point at least 1.5 cm below the rim and not under the container's base. A
    banana longer than a bowl is wide lies across it, its middle sunk in: that is inside; an
    object balanced on the rim is not."""
    o, c = state.box(obj), state.box(container)
    if _horizontal(o.centre, c.centre) > INSIDE_MAX_CENTRE_DIST:
        return False
    if not state.in_footprint(o.centre, container):
        return False
    return c.bottom - FLOOR_TOL <= o.bottom <= c.top - INSIDE_BELOW_RIM


def is_on(state: GoalState, obj: str, support: str) -> bool:
    """Object resting on top of ``support``: centre over it, bottom at its top (± a gap)."""
    o, top = state.box(obj), state.surface(support)
    if not state.in_footprint(o.centre, support):
        return False
    return top - ON_GAP_BELOW <= o.bottom <= top + ON_GAP_ABOVE


def is_upright(state: GoalState, obj: str) -> bool:
    """Object's z axis within 20° of world z."""
    zz = float(state.data.body(obj).xmat[8])
    return zz >= math.cos(math.radians(UPRIGHT_MAX_TILT_DEG))


def is_off_surface(state: GoalState, obj: str, surface: str) -> bool:
    """Object no longer above or on ``surface``: outside its footprint, or below its top."""
    o, s = state.box(obj), state.box(surface)
    return not state.in_footprint(o.centre, surface) or o.top < s.top


def is_near(state: GoalState, obj: str, target: str) -> bool:
    """Object's centre at most 0.15 m (horizontally) from the target's footprint, and not on
    or in it.

    Measured to the footprint rather than the target's centre: from outside a basket
    (0.32 × 0.24 m), no centre comes within 0.15 m of the basket's centre.
    """
    o, t = state.box(obj), state.box(target)
    if state.in_footprint(o.centre, target) and o.bottom >= t.bottom + FLOOR_TOL:
        return False
    lo, hi = object_bounds(state.model, state.data, target, solid_only=True)
    nearest = np.clip(o.centre[:2], lo[:2], hi[:2])
    return _horizontal(o.centre, nearest) <= NEAR_DIST


def check_goal(state: GoalState, goal: Goal) -> bool:
    """Whether ``goal`` holds in ``state``; an unknown object or part makes it false."""
    known = set(state.objects) | set(state.parts)
    if goal.object not in known or (goal.target is not None and goal.target not in known):
        return False
    p, obj, target = goal.predicate, goal.object, goal.target or ""
    if p == "drawer_open":
        return obj in state.parts and state.joint_value(obj) > DRAWER_OPEN
    if p == "drawer_closed":
        return obj in state.parts and state.joint_value(obj) < DRAWER_CLOSED
    if p == "knob_rotated":
        return obj in state.parts and abs(math.degrees(state.joint_value(obj))) > KNOB_ROTATED_DEG
    if p == "upright":
        return obj in state.objects and is_upright(state, obj)
    if p == "inside":
        return is_inside(state, obj, target)
    if p in ("on", "stacked_on"):
        return is_on(state, obj, target)
    if p == "off_surface":
        return is_off_surface(state, obj, target)
    if p == "near":
        return is_near(state, obj, target)
    return False


def check_goals(
    episode: Episode,
    model: mujoco.MjModel,
    data: mujoco.MjData,
    goals: tuple[Goal, ...] | None = None,
) -> tuple[bool, ...]:
    """Each goal's truth on the current state (``episode.goals`` by default)."""
    mujoco.mj_kinematics(model, data)
    state = GoalState(episode, model, data)
    return tuple(check_goal(state, g) for g in (episode.goals if goals is None else goals))


def describe_goal(goal: Goal) -> str:
    """``predicate(object[, target])``, as failure reasons show it."""
    args = goal.object if goal.target is None else f"{goal.object}, {goal.target}"
    return f"{goal.predicate}({args})"
