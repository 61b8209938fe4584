"""Arm motions the scripted skills share: IK planning with collision checks, straight-line TCP
moves, finger-contact tests and small UAV base adjustments, all on one simulation loop."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np
from numpy.typing import NDArray

from vlm_bench.executor.ik import SEED_POSTURES, ArmIk
from vlm_bench.executor.loop import SimLoop
from vlm_bench.executor.motion import min_jerk
from vlm_bench.executor.uav_move import fly_to
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.robot import arm_qpos, set_arm_targets

Vec = NDArray[np.float64]
IK_OK = 0.02  # residual (m + rad) accepted
BASE_ASSIST = tuple(np.array([0.0, 0.0, dz]) for dz in (0.0, -0.06, -0.12))
"""UAV moves (m) tried, in order, when the arm alone cannot reach: descents."""
INNER_EDGE = 0.30  # m, horizontal: closer to the arm base, a top-down reach folds the elbow
BACK_OFF_TO = 0.36  # m, horizontal: where backing away puts such a point


class Arm:
    """The arm of one simulation loop, with its IK solver.

    Args:
        loop: The loop the skills run on.
    """

    def __init__(self, loop: SimLoop) -> None:
        self.loop = loop
        self.ik = ArmIk(loop.model)
        self._fingers = {
            side: set(subtree_geoms(loop.model, loop.model.body(name).id))
            for side, name in (("l", c.LEFT_FINGER_BODY), ("r", c.RIGHT_FINGER_BODY))
        }

    def solve_any(
        self, point: Vec, rotation: Vec, seed: Vec, base: Vec | None = None
    ) -> tuple[Vec, float]:
        """IK from ``seed``, then from the known postures, until one converges."""
        best: tuple[Vec, float] = (seed, math.inf)
        for start in (seed, *SEED_POSTURES):
            q, res = self.ik.solve(self.loop.data, point, rotation, np.asarray(start), base=base)
            if res < best[1]:
                best = (q, res)
            if res < IK_OK:
                break
        return best

    def plan(
        self,
        point: Vec,
        approach: Vec,
        rotations: Sequence[Vec],
        ignore: set[int],
        gripper: float,
        seed: Vec,
        assist: Sequence[Vec] | None = None,
    ) -> tuple[Vec, Vec, Vec] | None:
        """Joint angles at ``point + approach``, the orientation and a base adjustment for a
        straight motion from there to ``point``.

        Of the candidate ``rotations``, prefer the one whose hand touches nothing outside
        ``ignore`` at both ends, then the one farthest from the joint limits. Where none
        reaches from the UAV's pose (a point at the inner edge of the workspace), the UAV may
        move by one of ``assist`` (tried in order; default :meth:`assists`).
        """
        data = self.loop.data
        if assist is None:
            assist = self.assists(point)
        best: tuple[Vec, Vec, Vec] | None = None
        for shift in assist:
            best, best_key = None, (math.inf, -math.inf)
            for rot in rotations:
                q_end, res = self.solve_any(point, rot, seed, shift)
                if res > IK_OK:
                    continue
                q_start, res = self.ik.solve(data, point + approach, rot, q_end, base=shift)
                if res > IK_OK:
                    continue
                hits = len(self.ik.collisions(data, q_end, ignore, gripper, shift))
                hits += len(self.ik.collisions(data, q_start, ignore, gripper, shift))
                margin = self.ik.limit_margin(q_end)
                key = (float(hits), -margin)
                if key < best_key:
                    best, best_key = (q_start, rot, shift), key
            if best is not None and best_key[0] == 0:
                return best
        return best

    def back_off(self, point: Vec, within: float, to: float) -> Vec | None:
        """The horizontal UAV move that puts ``point`` ``to`` m (horizontally) from the arm
        base, when it now lies closer than ``within`` (and not right below it)."""
        base = self.loop.data.body(c.ARM_BASE_BODY).xpos
        away = base[:2] - np.asarray(point)[:2]
        dist = float(np.linalg.norm(away))
        if not 1e-6 < dist < within:
            return None
        return np.append(away / dist * (to - dist), 0.0)

    def assists(self, point: Vec) -> list[Vec]:
        """UAV moves that may bring ``point`` into the arm's top-down workspace: none, small
        descents, then backing away horizontally where the point lies inside its inner edge."""
        shifts = list(BASE_ASSIST)
        back = self.back_off(point, INNER_EDGE, BACK_OFF_TO)
        if back is not None:
            shifts += [back, back + BASE_ASSIST[1]]
        return shifts

    def shift_base(self, delta: Vec) -> None:
        """Fly the UAV's setpoint by ``delta`` (m, world) and let it settle."""
        if np.any(delta):
            target = np.array(self.loop.controller.setpoint) + np.asarray(delta)
            fly_to(self.loop, target, self.loop.config.flight)

    def carry(self, delta: Vec, speed: float) -> None:
        """Fly the UAV by ``delta`` (m, world) at ``speed`` with the arm's targets held, so
        the hand moves with the base (pushing, or pulling a drawer, farther than the arm
        reaches)."""
        flight = self.loop.config.flight
        slow = flight.model_copy(update={"speed": min(speed, flight.speed), "accel": 0.25})
        target = np.array(self.loop.controller.setpoint) + np.asarray(delta)
        fly_to(self.loop, target, slow)

    def line(self, start: Vec, end: Vec, rotation: Vec, seconds: float, gripper: float) -> bool:
        """Move the TCP along the straight line ``start`` → ``end`` (minimum-jerk timing)
        keeping ``rotation``; ``False`` where IK loses the line."""
        n = max(2, round(seconds / c.CONTROL_DT))
        return self.follow(
            ((start + (end - start) * min_jerk(i / n), rotation) for i in range(1, n + 1)),
            gripper,
        )

    def follow(self, poses: Iterable[tuple[Vec, Vec]], gripper: float) -> bool:
        """Servo the TCP through ``poses`` (position, orientation), one per control step,
        each solved from the last; ``False`` (stopping there) where IK loses the path."""
        loop = self.loop
        q = arm_qpos(loop.model, loop.data)
        for point, rotation in poses:
            q, res = self.ik.solve(loop.data, point, rotation, q, iterations=60)
            if res > 3 * IK_OK:
                return False
            set_arm_targets(loop.model, loop.data, q, gripper)
            loop.control_step()
        return True

    def tcp(self) -> tuple[Vec, Vec]:
        """The TCP's position and orientation now (world)."""
        site = self.loop.data.site(c.TCP_SITE)
        return np.array(site.xpos), np.array(site.xmat).reshape(3, 3)

    def touching(self, geoms: set[int]) -> bool:
        """Whether both fingers touch one of ``geoms``."""
        hit = {"l": False, "r": False}
        d = self.loop.data
        for i in range(d.ncon):
            g1, g2 = int(d.contact.geom[i][0]), int(d.contact.geom[i][1])
            for side, fingers in self._fingers.items():
                if (g1 in fingers and g2 in geoms) or (g2 in fingers and g1 in geoms):
                    hit[side] = True
        return hit["l"] and hit["r"]

    def body_geoms(self, body: str) -> set[int]:
        """Geoms of ``body`` and its children."""
        return set(subtree_geoms(self.loop.model, self.loop.model.body(body).id))

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        return self.touching(self.body_geoms(obj))
