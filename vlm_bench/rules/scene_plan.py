"""A plan from the scene as text and the ARM steps: the prompt's rules, applied literally.

This is what a planner with perfect perception (the scene text) and perfect language (the ARM
steps an instruction asks for) writes by following the prompt: the ``rules`` planner and the
few-shot examples derive their UAV moves here, with the same :func:`approach_moves` the GT
builder uses. The scene is tracked as the prompt says it changes: a picked object travels with
the gripper, a placed one rests where it was placed, a pulled drawer is ``DRAWER_PULL`` open
and a closed one shut (its handle and inside move with it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from vlm_bench.rules.approach import Leg, UavState, WorkPoint, approach_moves
from vlm_bench.rules.scene_text import SceneEntry
from vlm_bench.rules.work import DRAWER_PULL
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import ArmStep, UavStep

Xyz = tuple[float, float, float]


def _xyz(body: Sequence[float]) -> Xyz:
    """Body (right, forward, up) → planar frame (x forward, y left, z up)."""
    return body[1], -body[0], body[2]


@dataclass
class _Thing:
    point: Xyz
    rest: Xyz | None
    tall: float
    standoff: float | None
    opening: float
    pull: tuple[float, float] | None

    def shift(self, dx: float, dy: float, dz: float) -> None:
        self.point = (self.point[0] + dx, self.point[1] + dy, self.point[2] + dz)
        if self.rest is not None:
            self.rest = (self.rest[0] + dx, self.rest[1] + dy, self.rest[2] + dz)


def _things(entries: Sequence[SceneEntry]) -> dict[str, _Thing]:
    return {
        e.id: _Thing(
            point=_xyz(e.point),
            rest=None if e.rest is None else _xyz(e.rest),
            tall=e.tall or 0.0,
            standoff=e.standoff,
            opening=e.opening or 0.0,
            pull=None if e.pull is None else (e.pull[1], -e.pull[0]),
        )
        for e in entries
    }


def _work_point(
    things: dict[str, _Thing], step: ArmStep, held: str | None, geo: ApproachGeometry
) -> WorkPoint | None:
    thing = things.get(step.object)
    if thing is None:
        return None
    standoff = thing.standoff if thing.standoff is not None else geo.standoff_horizontal
    if step.skill == "place" and held in things and thing.rest is not None:
        rx, ry, rz = thing.rest
        return WorkPoint(rx, ry, rz + things[held].tall / 2, standoff)
    return WorkPoint(*thing.point, standoff)


def _apply(things: dict[str, _Thing], step: ArmStep, held: str | None) -> str | None:
    """The scene after ``step``; returns what the gripper holds."""
    thing = things.get(step.object)
    if step.skill == "pick":
        return step.object
    if step.skill == "place" and held in things and thing is not None and thing.rest is not None:
        moved = things[held]
        rx, ry, rz = thing.rest
        x, y, z = moved.point
        moved.shift(rx - x, ry - y, rz + moved.tall / 2 - z)
        return None
    if step.skill in ("pull", "close") and thing is not None and thing.pull is not None:
        new = DRAWER_PULL if step.skill == "pull" else 0.0
        d = new - thing.opening
        thing.shift(thing.pull[0] * d, thing.pull[1] * d, 0.0)
        thing.opening = new
    return held


@dataclass(frozen=True)
class Segment:
    """One ARM step with the UAV moves the rules put before it."""

    step: ArmStep
    uav: UavState
    """The UAV before the moves."""
    point: WorkPoint | None
    """The step's working point (None: the object is not in the scene)."""
    legs: tuple[Leg, ...]


def plan_segments(
    entries: Sequence[SceneEntry],
    arm_steps: Sequence[ArmStep],
    geo: ApproachGeometry = APPROACH,
    held: str | None = None,
) -> list[Segment]:
    """Each ARM step with its working point and the moves before it (see module doc);
    ``held``: what the gripper holds at the start (a replan's)."""
    things = _things(entries)
    uav = UavState(0.0, 0.0, 0.0, 0.0)
    out: list[Segment] = []
    for step in arm_steps:
        point = _work_point(things, step, held, geo)
        legs = tuple(approach_moves(uav, point, geo)) if point is not None else ()
        out.append(Segment(step, uav, point, legs))
        if legs:
            uav = legs[-1].end
        held = _apply(things, step, held)
    return out


def plan_from_scene(
    entries: Sequence[SceneEntry],
    arm_steps: Sequence[ArmStep],
    geo: ApproachGeometry = APPROACH,
    held: str | None = None,
) -> list[UavStep | ArmStep]:
    """The full plan: before each ARM step, the UAV moves the rules give (see module doc)."""
    plan: list[UavStep | ArmStep] = []
    for segment in plan_segments(entries, arm_steps, geo, held):
        plan.extend(UavStep(direction=leg.direction) for leg in segment.legs)
        plan.append(segment.step)
    return plan
