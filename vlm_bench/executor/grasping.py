"""Scripted top-down ``pick`` and ``place`` with IK and real contact physics (no welds).

Pick: open, move (joint-space, minimum-jerk) to a pre-grasp 0.12 m above the object with the
hand pointing down, descend along a straight line, close, lift 0.15 m. It succeeds only if both
fingers touch the object and the object has risen. Place: move above the destination, lower,
open, retreat up and stow.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world import object_kind
from vlm_bench.executor.ik import TOP_DOWN_SEED, ArmIk
from vlm_bench.executor.loop import ArmSkill, SimLoop
from vlm_bench.executor.uav_move import stow_arm
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import object_bounds, subtree_geoms
from vlm_bench.sim.robot import arm_qpos, gripper_opening, set_arm_targets
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep

Vec = NDArray[np.float64]
PRE_GRASP = 0.12  # m above the grasp point
LIFT = 0.15  # m
IK_OK = 0.02  # residual (m + rad) accepted
MIN_LIFT = 0.08  # m the object must rise for a pick to count


def _min_jerk(s: float) -> float:
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def _joint_move(loop: SimLoop, goal: Vec, seconds: float, gripper: float | None = None) -> None:
    q0 = arm_qpos(loop.model, loop.data)
    grip = gripper_opening(loop.model, loop.data) if gripper is None else gripper
    n = max(1, round(seconds / c.CONTROL_DT))
    for i in range(1, n + 1):
        set_arm_targets(loop.model, loop.data, q0 + (goal - q0) * _min_jerk(i / n), grip)
        loop.control_step()


def _hold(loop: SimLoop, seconds: float, gripper: float) -> None:
    set_arm_targets(loop.model, loop.data, _targets(loop), gripper)
    for _ in range(max(1, round(seconds / c.CONTROL_DT))):
        loop.control_step()


def _targets(loop: SimLoop) -> Vec:
    return np.array([loop.data.ctrl[loop.model.actuator(a).id] for a in c.ARM_ACTUATORS])


class Grasper:
    """Pick and place for one scene; remembers what it holds."""

    def __init__(self, loop: SimLoop) -> None:
        self.loop = loop
        self.ik = ArmIk(loop.model)
        self.held: str | None = None
        self._fingers = {
            side: set(subtree_geoms(loop.model, loop.model.body(name).id))
            for side, name in (("l", c.LEFT_FINGER_BODY), ("r", c.RIGHT_FINGER_BODY))
        }

    def _solve(self, pos: Vec, yaw_rad: float, seed: Vec) -> tuple[Vec, float] | None:
        """Top-down IK over the four headings equivalent for a box-like object or a held one;
        of the solutions, the one farthest from the joint limits (room for the next motion)."""
        best: tuple[Vec, float] | None = None
        best_margin = -math.inf
        for k in range(4):
            heading = yaw_rad + k * math.pi / 2
            q, res = self.ik.solve(self.loop.data, pos, heading, seed)
            margin = float(np.min(np.minimum(q - self.ik.lo, self.ik.hi - q)))
            if res < IK_OK and margin > best_margin:
                best, best_margin = (q, heading), margin
        return best

    def _line(self, start: Vec, end: Vec, heading: float, seconds: float, gripper: float) -> bool:
        n = max(2, round(seconds / c.CONTROL_DT))
        q = arm_qpos(self.loop.model, self.loop.data)
        for i in range(1, n + 1):
            point = start + (end - start) * _min_jerk(i / n)
            q, res = self.ik.solve(self.loop.data, point, heading, q, iterations=60)
            if res > 3 * IK_OK:
                return False
            set_arm_targets(self.loop.model, self.loop.data, q, gripper)
            self.loop.control_step()
        return True

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        geoms = set(subtree_geoms(self.loop.model, self.loop.model.body(obj).id))
        hit = {"l": False, "r": False}
        d = self.loop.data
        for i in range(d.ncon):
            g1, g2 = int(d.contact.geom[i][0]), int(d.contact.geom[i][1])
            for side, fingers in self._fingers.items():
                if (g1 in fingers and g2 in geoms) or (g2 in fingers and g1 in geoms):
                    hit[side] = True
        return hit["l"] and hit["r"]

    def pick(self, episode: Episode, step: ArmStep) -> str | None:
        """Top-down grasp of ``step.object``; ``None`` on success, else the reason."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return f"unknown object {obj!r}"
        if self.held is not None:
            return f"already holding {self.held}"
        if not object_kind(kinds[obj]).graspable:
            return f"{obj} cannot be grasped"
        lo, hi = object_bounds(loop.model, loop.data, obj, solid_only=True)
        grasp = np.array(
            [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, max(lo[2] + 0.015, hi[2] - 0.03)]
        )
        rot = loop.data.body(obj).xmat.reshape(3, 3)
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        above = grasp + np.array([0.0, 0.0, PRE_GRASP])
        sol = self._solve(above, yaw, np.asarray(TOP_DOWN_SEED))
        if sol is None:
            return f"{obj} is out of reach"
        q_pre, heading = sol
        _joint_move(loop, q_pre, 2.5, c.GRIPPER_OPEN)
        _hold(loop, 0.3, c.GRIPPER_OPEN)
        if not self._line(above, grasp, heading, 1.5, c.GRIPPER_OPEN):
            return f"{obj} is out of reach"
        _hold(loop, 0.3, c.GRIPPER_OPEN)
        _hold(loop, 1.0, c.GRIPPER_CLOSED)
        z0 = float(loop.data.body(obj).xpos[2])
        if not self._line(
            grasp, grasp + np.array([0.0, 0.0, LIFT]), heading, 1.5, c.GRIPPER_CLOSED
        ):
            return "cannot lift: out of reach"
        _hold(loop, 0.3, c.GRIPPER_CLOSED)
        if not self.touching_fingers(obj) or loop.data.body(obj).xpos[2] - z0 < MIN_LIFT:
            return f"grasp of {obj} failed"
        self.held = obj
        return None

    def place(self, episode: Episode, step: ArmStep) -> str | None:
        """Lower the held object onto/into ``step.object`` and release it."""
        loop, dest = self.loop, step.object
        if self.held is None:
            return "nothing held"
        if dest not in episode.object_ids():
            return f"unknown object {dest!r}"
        held = self.held
        hlo, _ = object_bounds(loop.model, loop.data, held, solid_only=True)
        tcp = loop.data.site(c.TCP_SITE).xpos
        hang = float(tcp[2] - hlo[2])  # TCP height above the held object's bottom
        dlo, dhi = object_bounds(loop.model, loop.data, dest, solid_only=True)
        centre = (dlo + dhi) / 2
        release = np.array([centre[0], centre[1], dhi[2] + hang + 0.02])
        kinds = {o.id: object_kind(o.kind) for o in episode.objects}
        if dest in kinds and kinds[dest].container and not kinds[dest].support:
            release[2] = dlo[2] + 0.015 + hang + 0.02
        above = release + np.array([0.0, 0.0, max(0.0, dhi[2] + hang + 0.05 - release[2])])
        rot = loop.data.site(c.TCP_SITE).xmat.reshape(3, 3)
        heading = math.atan2(rot[1, 0], rot[0, 0])
        start = tcp.copy()
        lift_to = np.array([start[0], start[1], max(start[2], above[2])])
        if not self._line(start, lift_to, heading, 0.8, c.GRIPPER_CLOSED):
            return f"{dest} is out of reach"
        sol = self._solve(above, heading, arm_qpos(loop.model, loop.data))
        if sol is None:
            return f"{dest} is out of reach"
        q_above, heading = sol
        _joint_move(loop, q_above, 2.0, c.GRIPPER_CLOSED)
        if not self._line(above, release, heading, 1.2, c.GRIPPER_CLOSED):
            return f"{dest} is out of reach"
        _hold(loop, 0.6, c.GRIPPER_OPEN)
        self.held = None
        up = release + np.array([0.0, 0.0, 0.12])
        self._line(release, up, heading, 1.0, c.GRIPPER_OPEN)
        stow_arm(loop, loop.config.flight)
        return None


def grasp_skills(loop: SimLoop) -> dict[str, ArmSkill]:
    """``pick`` and ``place`` bound to one loop (they share what is held)."""
    grasper = Grasper(loop)
    return {
        "pick": lambda _loop, episode, step: grasper.pick(episode, step),
        "place": lambda _loop, episode, step: grasper.place(episode, step),
    }
