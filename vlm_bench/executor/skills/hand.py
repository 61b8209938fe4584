"""The arm and hand the scripted skills share on one loop: planning, lines, flights, contacts.

One :class:`Hand` per loop serves every skill, so what the hand holds (``loop.held``) and the
planners' caches are shared.
"""

from __future__ import annotations

import numpy as np

from vlm_bench.executor.motion.arm_core import ArmCore
from vlm_bench.executor.motion.arm_planner import ArmPlanner
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.flight_clearance import FlightClearance
from vlm_bench.executor.motion.lines import ArmLines
from vlm_bench.executor.motion.stow_clear import stow_clear
from vlm_bench.executor.motion.uav_moves import carry, shift_base
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import LEFT_FINGER_BODY, RIGHT_FINGER_BODY
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.types.base import FloatArray

# How far the open hand withdraws at least after letting go: two moves, two distances.
RELEASE_RISE = 0.12  # m: up, after a place releases the object
HANDLE_BACK_OFF = 0.08  # m: back from a drawer's handle, after a pull or close


class Hand:
    """The arm of one loop as the skills use it.

    Attributes:
        core: IK, collision queries, the held object.
        lines: Straight TCP motions.
        planner: Reach planning.
        flight: Flights with an object in the hand.
    """

    def __init__(self, loop: SimLoop) -> None:
        self.loop = loop
        self.core = ArmCore(loop)
        self.lines = ArmLines(self.core)
        self.planner = ArmPlanner(self.core, self.lines)
        self.flight = FlightClearance(self.core)
        self._fingers = {
            side: set(subtree_geoms(loop.model, loop.model.body(name).id))
            for side, name in (("l", LEFT_FINGER_BODY), ("r", RIGHT_FINGER_BODY))
        }

    def shift_base(self, move: BaseMove) -> None:
        """Fly the UAV by ``move`` (see :func:`~vlm_bench.executor.motion.uav_moves.shift_base`)."""
        shift_base(self.loop, move)

    def carry(self, delta: FloatArray, speed: float) -> None:
        """Fly the UAV by ``delta`` (m) at ``speed`` with the arm's targets held."""
        carry(self.loop, delta, speed)

    def stow(self) -> FloatArray:
        """Stow the arm by a clear way; the UAV's climb made for it (m, world)."""
        return stow_clear(self.core, self.flight)

    def tcp(self) -> tuple[FloatArray, FloatArray]:
        """The TCP's position and orientation now (world)."""
        return self.core.tcp()

    def body_geoms(self, body: str) -> set[int]:
        """Geoms of ``body`` and its children."""
        return self.core.body_geoms(body)

    def touching(self, geoms: set[int]) -> bool:
        """Whether both fingers touch one of ``geoms``."""
        return all(self.in_contact(fingers, geoms) for fingers in self._fingers.values())

    def in_contact(self, geoms: set[int], others: set[int]) -> bool:
        """Whether one of ``geoms`` touches one of ``others`` now."""
        d = self.loop.data
        for i in range(d.ncon):
            g1, g2 = int(d.contact.geom[i][0]), int(d.contact.geom[i][1])
            if (g1 in geoms and g2 in others) or (g2 in geoms and g1 in others):
                return True
        return False

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        return self.touching(self.body_geoms(obj))

    def outward_axis(self, body: str) -> FloatArray:
        """``body``'s x axis made horizontal and unit (a cabinet's front normal), world."""
        axis: FloatArray = np.array(self.loop.data.body(body).xmat).reshape(3, 3)[:, 0]
        axis[2] = 0.0
        return axis / float(np.linalg.norm(axis))
