"""``slip=P``: a held object drops during a carry (docs/closed-loop.md#perturbations).

A carry is everything from a pick to the next place of the object, however many flights it
takes. When a carry's first flight starts with the object in the fingers, it draws once, keyed by
what happens (the episode, the object, the carry's destination, the n-th attempt of that carry):
with probability P the fingers open when the UAV has flown a drawn fraction of the carry's
planned flying (the UAV moves from the pick to the place), at the end of its last flight at the
latest; the robot does not notice until a skill needs it (``place`` fails ``slipped``). A carry
split into two legs meets the same draw as one leg; a carry retried after a slip draws afresh.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from vlm_bench.executor.motion.joint_moves import hold_with_gripper
from vlm_bench.executor.perturbations.kind import PerturbationKind, event_rng
from vlm_bench.executor.perturbations.placement import in_fingers
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import GRIPPER_ACTUATOR, GRIPPER_OPEN
from vlm_bench.types.closed_loop import PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep, PlanSteps, UavStep

SLIP_FRACTION = (0.1, 0.9)
"""Fraction of a carry's planned flying at which a slip drops the object."""
UNSTATED_LEG_M = 0.5
"""Planned length of a flight that states no distance (it flies to the next ARM step's object)."""
DROP_S = 0.6
"""Time the open fingers are held after a drop at a flight's end (s)."""


@dataclass
class _Carry:
    object: str
    drop_after_m: float | None
    """Flown path (m) at which the object drops (None: it does not)."""
    flown_m: float = 0.0
    start_s: float = 0.0


def carry_legs(plan: PlanSteps, index: int) -> tuple[str, float, bool]:
    """From flight ``index`` of ``plan``: the carry's destination (where the next place puts the
    held object; ``""`` where the plan has none), its planned flying from this flight on (m), and
    whether this flight is its last."""
    flying, legs = 0.0, 0
    for step in plan[index:]:
        if isinstance(step, UavStep):
            flying += step.distance if step.distance is not None else UNSTATED_LEG_M
            legs += 1
        elif step.skill == "place":
            return step.object, flying, legs == 1
    return "", flying, legs == 1


class Slip(PerturbationKind):
    """A held object slips out of the fingers during a carry (module doc)."""

    name = "slip"

    def __init__(self, rate: float, episode: Episode, emit: Callable[[PerturbEvent], None]):
        super().__init__(rate, episode, emit)
        self._attempts: dict[tuple[str, str], int] = {}
        self._carry: _Carry | None = None
        self._last_leg = False
        self._pos: np.ndarray | None = None
        self._step = 0

    def flight_started(self, loop: SimLoop, index: int, plan: PlanSteps) -> None:
        """Start (and draw) a carry where the hand holds an object and none is on."""
        held = loop.held
        carry = self._carry
        if carry is not None and carry.object != held:
            carry = self._carry = None  # dropped, or placed unnoticed
        if held is None or not in_fingers(loop, held):
            self._carry = None
            return  # nothing in the hand (a dropped object is gone until picked again)
        destination, planned, self._last_leg = carry_legs(plan, index)
        if carry is None:
            n = self._attempts.get((held, destination), 0)
            self._attempts[held, destination] = n + 1
            rng = event_rng(self.episode, self.name, held, destination, n)
            fires, fraction = rng.random() < self.rate, rng.uniform(*SLIP_FRACTION)
            carry = self._carry = _Carry(held, fraction * planned if fires else None)
            carry.start_s = loop.time
        if carry.drop_after_m is not None:
            self._step, self._pos = index, loop.uav_position()
            loop.observers.append(self._watch_flight)

    def _watch_flight(self, loop: SimLoop) -> None:
        carry = self._carry
        if carry is None or carry.drop_after_m is None or self._pos is None:
            return
        pos = loop.uav_position()
        carry.flown_m += float(np.linalg.norm(pos - self._pos))
        self._pos = pos
        if carry.flown_m >= carry.drop_after_m:
            self._drop(loop, carry)

    def flight_ended(self, loop: SimLoop) -> None:
        """At the carry's last flight's end, a drop still due happens now."""
        carry = self._carry
        if self._watch_flight in loop.observers:
            loop.observers.remove(self._watch_flight)
        if carry is not None and carry.drop_after_m is not None and self._last_leg:
            self._drop(loop, carry)
            hold_with_gripper(loop, DROP_S, GRIPPER_OPEN)

    def after_arm_step(self, loop: SimLoop, index: int, step: ArmStep, ok: bool) -> None:
        """A place (or a pick) ends the carry."""
        if step.skill in ("place", "pick"):
            self._carry = None

    def _drop(self, loop: SimLoop, carry: _Carry) -> None:
        carry.drop_after_m = None
        held = loop.held
        if held is None:
            return
        loop.data.ctrl[loop.model.actuator(GRIPPER_ACTUATOR).id] = GRIPPER_OPEN
        at = max(0.0, loop.time - carry.start_s)
        self.emit(PerturbEvent(kind="slip", step=self._step, object=held, at_s=round(at, 3)))
