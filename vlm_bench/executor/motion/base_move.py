"""A move of the UAV, the arm's base: an offset and a heading turn.

Skills plan their reaches with the UAV moved a little (a descent, a step back, a hover in front
of a drawer, sometimes turned); the planner checks the arm at the moved base and the skill then
flies the move (:func:`~vlm_bench.executor.motion.uav_moves.shift_base`) and undoes it after.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from vlm_bench.types.base import FloatArray


@dataclass(frozen=True, eq=False)
class BaseMove:
    """A UAV move: ``xyz`` (m, world) and a turn of its heading by ``yaw`` (rad, CCW), made at
    the move's higher end (:attr:`turns_first`)."""

    xyz: FloatArray
    yaw: float = 0.0

    @staticmethod
    def still() -> BaseMove:
        """No move."""
        return BaseMove(np.zeros(3))

    @staticmethod
    def vertical(dz: float) -> BaseMove:
        """A climb (``dz`` > 0) or descent (m)."""
        return BaseMove(np.array([0.0, 0.0, dz]))

    @property
    def turns_first(self) -> bool:
        """Whether the turn is made before the offset: for a descent, so the turn is made at
        the move's higher end."""
        return bool(self.xyz[2] < 0.0)

    def plus(self, xyz: FloatArray) -> BaseMove:
        """This move with ``xyz`` (m, world) added to its offset."""
        return BaseMove(self.xyz + xyz, self.yaw)

    def undo(self) -> BaseMove:
        """The move back: offset and turn negated."""
        return BaseMove(-self.xyz, -self.yaw)

    def key(self) -> bytes:
        """Hashable identity (for the IK and collision caches)."""
        return np.asarray(self.xyz, dtype=np.float64).tobytes() + np.float64(self.yaw).tobytes()

    def apply(self, qpos: FloatArray, adr: int) -> None:
        """Move the UAV's free joint at ``qpos[adr:adr + 7]`` by this move."""
        qpos[adr : adr + 3] += self.xyz
        if self.yaw:
            half = 0.5 * float(self.yaw)
            turned = np.empty(4)
            spin = np.array([math.cos(half), 0.0, 0.0, math.sin(half)])
            mujoco.mju_mulQuat(turned, spin, qpos[adr + 3 : adr + 7])
            qpos[adr + 3 : adr + 7] = turned
