"""Derive the GT plan from geometry: UAV moves are computed, never typed by hand.

Before each ARM step the moves of :func:`vlm_bench.rules.approach_moves` are inserted: a
horizontal move in the quantised body-frame bearing of the step's working point when it is out
of reach, and ``up`` (before it) or ``down`` (after it) when the working altitude differs by
more than a threshold. The prompt states the same rule from the same code. The UAV's pose is
tracked with ideal kinematics (the executor's stopping rule) and the scene's state is tracked
through the skills' effect models (:mod:`vlm_bench.rules.effects`, the ``rules`` planner's own:
picked objects travel, drawers open), so later steps are judged
from where things really are. Any decision that lies within a safety margin of its threshold,
and any leg that would sweep the UAV or its stowed arm through an obstacle, raises
:class:`AmbiguousGeometry`, and the caller resamples the seed: no GT depends on a judgement the
images cannot support.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes.plane_geometry import rect_corners, segment_rect_distance
from vlm_bench.rules import (
    DRAWER_FLOOR_BELOW_HANDLE,
    DRAWER_INSIDE_BEHIND_HANDLE,
    UavState,
    WorkPoint,
    approach_moves,
    rotate_xy,
)
from vlm_bench.rules.approach import ambiguity
from vlm_bench.rules.effects import Xyz, effect_of
from vlm_bench.rules.work import rest_height
from vlm_bench.types.episode import EpisodeObject, PartRef, UavPose
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.task import ArmStepSpec

UAV_CLEARANCE = 0.50  # m, rotor tip radius: horizontal clearance from tall fixtures
DRAWER_FRONT_ABOVE_HANDLE = 0.24  # m, top edge of a drawer front above its handle


class AmbiguousGeometry(ValueError):
    """A GT decision lies too close to a threshold (or is infeasible); resample."""


class PathBlocked(AmbiguousGeometry):
    """A flight segment would sweep the UAV or its stowed arm through an obstacle."""


@dataclass
class _State:
    uav_xy: tuple[float, float]
    uav_z: float
    yaw: float
    bottoms: dict[str, tuple[float, float, float]]
    openings: dict[str, float]
    held: str | None = None
    gone: set[str] = field(default_factory=set)


@dataclass(frozen=True)
class Reference:
    """Where the UAV approaches an ARM step's object: point (m, world) and horizontal stand-off."""

    x: float
    y: float
    z: float
    standoff: float


class GroundTruthBuilder:
    """Turns an ARM skeleton into a full GT plan for one layout and UAV start."""

    def __init__(
        self,
        objects: list[EpisodeObject],
        parts: list[PartRef],
        geometry: ApproachGeometry = APPROACH,
    ) -> None:
        self.geometry = geometry
        self.objects = {o.id: o for o in objects}
        self.parts = {p.id: p for p in parts}
        self._part_specs = {
            p.name: (p, self.objects[ref.parent])
            for ref in parts
            for p in object_kind(self.objects[ref.parent].kind).parts
            if p.name == ref.id
        }
        self._tall = [
            (o.id, rect_corners(o.pos, object_kind(o.kind).size[:2], o.yaw_deg), o.pos[2] + h)
            for o in objects
            if not object_kind(o.kind).movable
            for h in [object_kind(o.kind).size[2]]
        ]

    # ---- references -------------------------------------------------------------------
    def _ref(self, state: _State, obj_id: str) -> Reference:
        if obj_id in self.parts:
            spec, _ = self._part_specs[obj_id]
            hx, hy, hz = self._handle(state, obj_id)
            return Reference(hx, hy, hz, spec.standoff or self.geometry.standoff_horizontal)
        kind = object_kind(self.objects[obj_id].kind)
        bx, by, bz = state.bottoms[obj_id]
        return Reference(bx, by, bz + kind.size[2] / 2, self.geometry.standoff_horizontal)

    def _step_ref(self, state: _State, obj_id: str, skill: str) -> Reference:
        """Reference of an ARM step: where its skill's effect model says it works (a place: where
        the held object will rest, not the destination's centre)."""
        point = effect_of(skill).work_point(
            _Planning(self, state), ArmStep(object=obj_id, skill=skill)
        )
        if point is None:
            raise KeyError(obj_id)
        return Reference(point.x, point.y, point.z, point.standoff)

    def step_reference(
        self,
        obj_id: str,
        skill: str,
        bottoms: Mapping[str, tuple[float, float, float]],
        openings: Mapping[str, float],
        held: str | None = None,
    ) -> Reference | None:
        """The reference the GT uses for an ARM step, from a scene state (e.g. a live
        simulation's): object bottom centres, drawer openings and the held object.
        ``None`` if the step's object is not in the scene."""
        if obj_id not in self.objects and obj_id not in self.parts:
            return None
        state = _State(
            uav_xy=(0.0, 0.0),
            uav_z=0.0,
            yaw=0.0,
            bottoms=dict(bottoms),
            openings=dict(openings),
            held=held,
        )
        return self._step_ref(state, obj_id, skill)

    def _handle(self, state: _State, part: str) -> tuple[float, float, float]:
        """Handle position with the drawer's current opening along its owner's front axis."""
        spec, owner = self._part_specs[part]
        opening = state.openings.get(part, 0.0)
        lx, ly = rotate_xy(spec.handle[0] + opening, spec.handle[1], owner.yaw_deg)
        return owner.pos[0] + lx, owner.pos[1] + ly, owner.pos[2] + spec.handle[2]

    def _top_for(self, state: _State, dest: str) -> tuple[float, float, float]:
        """Where an object placed on/in ``dest`` rests (x, y, bottom z)."""
        if dest in self.parts:
            hx, hy, hz = self._handle(state, dest)
            _, owner = self._part_specs[dest]
            # The drawer's interior centre lies behind its handle, along the owner's front axis.
            bx, by = rotate_xy(-DRAWER_INSIDE_BEHIND_HANDLE, 0.0, owner.yaw_deg)
            return hx + bx, hy + by, hz - DRAWER_FLOOR_BELOW_HANDLE
        kind = object_kind(self.objects[dest].kind)
        bx, by, bz = state.bottoms[dest]
        return bx, by, rest_height(bz, kind.size[2], container=kind.container, support=kind.support)

    # ---- moves ------------------------------------------------------------------------
    def _check_path(self, a: tuple[float, float], b: tuple[float, float], z: float) -> None:
        stow_bottom = z - 0.5
        for obj_id, corners, top in self._tall:
            if top > stow_bottom and segment_rect_distance(a, b, corners) < UAV_CLEARANCE:
                raise PathBlocked(f"UAV path passes too close to {obj_id}")

    def _check_arm(
        self,
        state: _State,
        a: tuple[float, float],
        b: tuple[float, float],
        z: float,
        exclude: set[str],
    ) -> None:
        """The stowed arm, hanging below the UAV, must pass above every object on the way."""
        geo = self.geometry
        lowest = z - geo.stow_depth - geo.stow_clearance
        for obj_id, (bx, by, bz) in state.bottoms.items():
            if obj_id in exclude or obj_id in state.gone or obj_id == state.held:
                continue
            kind = object_kind(self.objects[obj_id].kind)
            if bz + kind.size[2] <= lowest:
                continue
            corners = rect_corners((bx, by), kind.size[:2], self.objects[obj_id].yaw_deg)
            if _approaches(a, b, corners, geo.stow_radius):
                raise PathBlocked(f"the stowed arm would hit {obj_id}")
        for part, corners, top in self._open_drawers(state):
            if part not in exclude and top > lowest and _approaches(a, b, corners, geo.stow_radius):
                raise PathBlocked(f"the stowed arm would hit the open {part}")

    def _open_drawers(self, state: _State) -> list[tuple[str, np.ndarray, float]]:
        """(part id, footprint corners, top z) of every open drawer, sticking out of the front
        of its cabinet."""
        out = []
        for name, (spec, owner) in self._part_specs.items():
            opening = state.openings.get(name, 0.0)
            if spec.kind != "drawer" or opening <= 0:
                continue
            depth, width, _ = object_kind(owner.kind).size
            dx, dy = rotate_xy(depth / 2 + opening / 2, 0.0, owner.yaw_deg)
            corners = rect_corners(
                (owner.pos[0] + dx, owner.pos[1] + dy), (opening + 0.04, width), owner.yaw_deg
            )
            out.append((name, corners, owner.pos[2] + spec.handle[2] + DRAWER_FRONT_ABOVE_HANDLE))
        return out

    def _approach(
        self, state: _State, ref: Reference, target: str
    ) -> list[tuple[UavStep, UavPose]]:
        """UAV moves that bring ``ref`` into reach (the rule of :func:`approach_moves`), each
        with the pose it ends at; every decision is checked for its margin and every leg for
        clearance."""
        geo = self.geometry
        uav = UavState(state.uav_xy[0], state.uav_xy[1], state.uav_z, state.yaw)
        point = WorkPoint(ref.x, ref.y, ref.z, ref.standoff)
        problem = ambiguity(uav, point, geo)
        if problem is not None:
            raise AmbiguousGeometry(problem)
        legs = approach_moves(uav, point, geo)
        steps: list[tuple[UavStep, UavPose]] = []
        for leg in legs:
            if not leg.vertical:  # a climb or descent in place sweeps nothing new
                self._check_path(leg.start.xy, leg.end.xy, leg.start.z)
                self._check_arm(state, leg.start.xy, leg.end.xy, leg.start.z, {target})
            state.uav_xy, state.uav_z = leg.end.xy, leg.end.z
            steps.append((UavStep(direction=leg.direction), _pose(state)))
        return steps

    def _initial_state(self, start: UavPose) -> _State:
        """Scene state at the episode start: objects where placed, drawers as initialised."""
        return _State(
            uav_xy=(start.pos[0], start.pos[1]),
            uav_z=start.pos[2],
            yaw=start.yaw_deg,
            bottoms={i: o.pos for i, o in self.objects.items()},
            openings={
                name: owner.initial.get(name, 0.0) for name, (_, owner) in self._part_specs.items()
            },
        )

    def first_reference(
        self, arm_steps: tuple[ArmStepSpec, ...]
    ) -> tuple[np.ndarray, tuple[float, float] | None]:
        """Reference point of the first ARM object and, for front-approached parts, its front
        axis (the UAV start is sampled around it)."""
        first = arm_steps[0].object
        ref = self._ref(self._initial_state(UavPose(pos=(0.0, 0.0, 0.0), yaw_deg=0.0)), first)
        front = None
        if first in self.parts:
            spec, owner = self._part_specs[first]
            if spec.approach_front:
                front = rotate_xy(1.0, 0.0, owner.yaw_deg)
        return np.array([ref.x, ref.y, ref.z]), front

    # ---- public -----------------------------------------------------------------------
    def build(
        self, start: UavPose, arm_steps: tuple[ArmStepSpec, ...]
    ) -> tuple[list[UavStep | ArmStep], list[UavPose]]:
        """GT plan and the UAV pose after each of its steps."""
        state = self._initial_state(start)
        self._check_arm(state, state.uav_xy, state.uav_xy, state.uav_z, set())
        plan: list[UavStep | ArmStep] = []
        poses: list[UavPose] = []
        for spec in arm_steps:
            ref = self._step_ref(state, spec.object, spec.skill)
            for move, pose in self._approach(state, ref, spec.object):
                plan.append(move)
                poses.append(pose)
            step = ArmStep(object=spec.object, skill=spec.skill, target=spec.target)
            plan.append(step)
            poses.append(_pose(state))
            effect_of(spec.skill).apply(_Planning(self, state), step)
        return plan, poses


def _approaches(
    a: tuple[float, float], b: tuple[float, float], corners: np.ndarray, radius: float
) -> bool:
    """Whether segment a→b comes within ``radius`` of a rectangle, other than by starting there
    and moving away (the arm got there legitimately: it was working at that obstacle)."""
    closest = segment_rect_distance(a, b, corners)
    return closest < radius and closest < segment_rect_distance(a, a, corners) - 1e-9


def _pose(state: _State) -> UavPose:
    return UavPose(pos=(state.uav_xy[0], state.uav_xy[1], state.uav_z), yaw_deg=state.yaw)


class _Planning:
    """The GT's state seen by the skills' effect models (world frame; see
    :class:`vlm_bench.rules.effects.PlanningState`)."""

    def __init__(self, builder: GroundTruthBuilder, state: _State) -> None:
        self.builder, self.state = builder, state

    @property
    def held(self) -> str | None:
        return self.state.held

    def hold(self, item: str | None) -> None:
        self.state.held = item

    def _knows(self, item: str) -> bool:
        return item in self.builder.objects or item in self.builder.parts

    def reference(self, item: str) -> WorkPoint | None:
        if not self._knows(item):
            return None
        ref = self.builder._ref(self.state, item)
        return WorkPoint(ref.x, ref.y, ref.z, ref.standoff)

    def height(self, item: str) -> float | None:
        obj = self.builder.objects.get(item)
        return None if obj is None else object_kind(obj.kind).size[2]

    def rest_on(self, item: str) -> Xyz | None:
        return self.builder._top_for(self.state, item) if self._knows(item) else None

    def bottom(self, item: str) -> Xyz | None:
        return self.state.bottoms.get(item)

    def set_bottom(self, item: str, bottom: Xyz) -> None:
        self.state.bottoms[item] = bottom

    def is_drawer(self, item: str) -> bool:
        spec = self.builder._part_specs.get(item)
        return spec is not None and spec[0].kind == "drawer"

    def set_opening(self, item: str, opening: float) -> None:
        self.state.openings[item] = opening

    def remove(self, item: str) -> None:
        self.state.gone.add(item)
