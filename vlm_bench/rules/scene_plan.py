"""A plan from the scene as text and the ARM steps: the prompt's rules, applied literally.

This is what a planner with perfect perception (the scene text) and perfect language (the ARM
steps an instruction asks for) writes by following the prompt: the ``rules`` planner and the
few-shot examples derive their UAV moves here, with the same :func:`approach_moves` the GT
builder uses. The scene is tracked as the prompt says it changes: a picked object travels with
the gripper, a placed one rests where it was placed, a pulled drawer is ``DRAWER_PULL`` open
and a closed one shut (its handle and inside move with it): each skill's effect model
(:mod:`vlm_bench.rules.effects`), the GT builder's own.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from vlm_bench.rules.approach import Leg, UavState, WorkPoint, approach_moves
from vlm_bench.rules.effects import Xyz, effect_of
from vlm_bench.rules.scene_text import SceneEntry
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import ArmStep, UavStep


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


class SceneState:
    """The scene as the scene text gives it (planar frame: x forward, y left, z up, from the
    UAV's start), changed by the skills' effect models (:mod:`vlm_bench.rules.effects`)."""

    def __init__(
        self, entries: Sequence[SceneEntry], geo: ApproachGeometry, held: str | None = None
    ) -> None:
        self.geo = geo
        self._held = held
        self.things = {
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
        self.removed: set[str] = set()

    @property
    def held(self) -> str | None:
        """What the gripper holds."""
        return self._held

    def hold(self, item: str | None) -> None:
        self._held = item

    def reference(self, item: str) -> WorkPoint | None:
        thing = self.things.get(item)
        if thing is None:
            return None
        standoff = thing.standoff if thing.standoff is not None else self.geo.standoff_horizontal
        return WorkPoint(*thing.point, standoff)

    def height(self, item: str) -> float | None:
        thing = self.things.get(item)
        return None if thing is None else thing.tall

    def rest_on(self, item: str) -> Xyz | None:
        thing = self.things.get(item)
        return None if thing is None else thing.rest

    def bottom(self, item: str) -> Xyz | None:
        thing = self.things.get(item)
        if thing is None:
            return None
        x, y, z = thing.point
        return x, y, z - thing.tall / 2

    def set_bottom(self, item: str, bottom: Xyz) -> None:
        thing = self.things.get(item)
        if thing is not None:
            x, y, z = thing.point
            thing.shift(bottom[0] - x, bottom[1] - y, bottom[2] + thing.tall / 2 - z)

    def is_drawer(self, item: str) -> bool:
        thing = self.things.get(item)
        return thing is not None and thing.pull is not None

    def set_opening(self, item: str, opening: float) -> None:
        thing = self.things[item]
        if thing.pull is not None:
            d = opening - thing.opening
            thing.shift(thing.pull[0] * d, thing.pull[1] * d, 0.0)
        thing.opening = opening

    def remove(self, item: str) -> None:
        self.removed.add(item)


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
    state = SceneState(entries, geo, held)
    uav = UavState(0.0, 0.0, 0.0, 0.0)
    out: list[Segment] = []
    for step in arm_steps:
        effect = effect_of(step.skill)
        point = effect.work_point(state, step)
        legs = tuple(approach_moves(uav, point, geo)) if point is not None else ()
        out.append(Segment(step, uav, point, legs))
        if legs:
            uav = legs[-1].end
        effect.apply(state, step)
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
