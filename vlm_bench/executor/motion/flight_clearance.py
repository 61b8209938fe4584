"""Flights with an object in the hand: keeping the arm and what it holds clear of the scene.

The arm is stowed for flights only with an empty hand (folding a held object against the arm
knocks it out of the fingers), so a held object flies where the pick left it. Before such a
flight the arm's base joint may turn it aside, and the UAV may climb first.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np

from vlm_bench.executor.motion.arm_core import MIN_MARGIN, ArmCore
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.joint_moves import HELD_JOINT_SPEED, joint_move
from vlm_bench.sim.constants import GRIPPER_CLOSED
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray

CLIMBS = tuple(np.array([0.0, 0.0, dz]) for dz in (0.15, 0.3))
"""UAV climbs (m) tried, least first, where a level way is not clear."""
FLIGHT_CLEARANCE = 0.03  # m a flight with an object in the hand keeps from everything, if it can
FLIGHT_STEP = 0.05  # m between the collision checks of a flight with an object in the hand
CARRY_TURNS = tuple(sign * turn for turn in (0.4, 0.8, 1.2, 1.6) for sign in (1.0, -1.0))
"""Turns of the arm's base joint (rad) tried to carry a held object clear of a flight's way."""


class FlightClearance:
    """Clearing the way of a flight with an object in the hand.

    Args:
        core: The arm (IK, collision queries, the held object).
    """

    def __init__(self, core: ArmCore) -> None:
        self.core = core
        self.loop = core.loop

    def clear_for_flight(self, travel: FloatArray) -> float | None:
        """Before the UAV flies ``travel`` (m, world) with an object in the hand: where the
        robot or the object, carried as it hangs now, would come within
        :data:`FLIGHT_CLEARANCE` of something on the way (a drawer's front the flight stops
        at), turn the arm's base joint, smallest turn first, to a posture from which the whole
        flight keeps that clear (else, failing any, merely touches nothing: the flying UAV
        sways, so a path planned to pass an obstacle by less than its sway is not clear). The
        turn made (rad, 0 for none; undo it with :meth:`turn_back` after the flight), ``None``
        where no turn clears the flight."""
        if self.loop.held is None:
            return 0.0
        now = arm_qpos(self.loop.model, self.loop.data)
        for clearance in (FLIGHT_CLEARANCE, 0.0):
            clear = functools.partial(self.flight_clear, travel, clearance=clearance)
            if clear(now):
                return 0.0
            for turn in CARRY_TURNS:
                if self._turn(turn, clear):
                    return turn
        return None

    def flight_climb(self, travel: FloatArray) -> FloatArray:
        """Where no turn clears a flight of ``travel`` (m, world) with an object in the hand:
        the least of :data:`CLIMBS` for the UAV to climb first and fly the flight that much
        higher, both clear (an arm left reaching out low can end a level flight in what
        stands beside its stop); none (zeros) where neither is clear."""
        for climb in CLIMBS:
            if self.flight_clear(climb) and self.flight_clear(travel, start=climb):
                return climb
        return np.zeros(3)

    def flight_clear(
        self,
        travel: FloatArray,
        q: FloatArray | None = None,
        clearance: float = 0.0,
        start: FloatArray | None = None,
    ) -> bool:
        """Whether the robot, with arm angles ``q`` (default: as now) and the held object
        carried, touches nothing (comes no closer than ``clearance``, m) while the UAV flies
        ``travel`` (m, world), from where it is (or moved by ``start``)."""
        data, carried = self.loop.data, self.core.carried()
        q = arm_qpos(self.loop.model, data) if q is None else q
        n = max(1, math.ceil(float(np.linalg.norm(travel)) / FLIGHT_STEP))
        first = np.zeros(3) if start is None else np.asarray(start)
        ways = [BaseMove(first + np.asarray(travel) * k / n) for k in range(n + 1)]
        return not any(
            self.core.collisions(q, CollisionQuery.of(set(), None, b, carried, clearance))
            for b in ways
        )

    def turn_back(self, turn: float | None) -> None:
        """Undo :meth:`clear_for_flight`'s turn of the base joint after the flight: a base
        joint left turned near its limit leaves a later place no way to its release but a
        wide swing, which flings a held object."""
        if turn:
            self._turn(-turn, lambda _q: True)

    def _turn(self, turn: float, clear: Callable[[FloatArray], bool]) -> bool:
        """Turn the base joint by ``turn`` (rad), holding the object, where the posture it
        ends in keeps off the joint limits and is ``clear`` and the way there touches
        nothing; whether it turned."""
        now = arm_qpos(self.loop.model, self.loop.data)
        q = now.copy()
        q[0] += turn
        if self.core.ik.limit_margin(q) < MIN_MARGIN or not clear(q):
            return False
        query = CollisionQuery.of(set(), GRIPPER_CLOSED, BaseMove.still(), self.core.carried())
        if self.core.path_hits(now, q, query, limit=0):
            return False
        joint_move(self.loop, q, 1.0, None, HELD_JOINT_SPEED)
        return True
