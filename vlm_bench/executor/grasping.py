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
from vlm_bench.episodes.layout import CONTAINER_FLOOR
from vlm_bench.executor.arm import Arm
from vlm_bench.executor.grasp_points import grasp_points
from vlm_bench.executor.ik import TOP_DOWN_SEED, top_down_rotation
from vlm_bench.executor.loop import ArmSkill, SimLoop
from vlm_bench.executor.motion import hold_with_gripper, joint_move
from vlm_bench.executor.uav_move import stow_arm
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.world import ObjectKind

Vec = NDArray[np.float64]
PRE_GRASP = 0.12  # m above the grasp point
LIFT = 0.15  # m
MIN_LIFT = 0.08  # m the object must rise for a pick to count
INNER_REACH = 0.30  # m, horizontal: top-down releases closer to the arm base are moved out


class Grasper:
    """Pick and place for one scene (what is held lives in ``loop.held``)."""

    def __init__(self, loop: SimLoop, arm: Arm | None = None) -> None:
        self.loop = loop
        self.arm = arm or Arm(loop)

    def _plan_top_down(
        self,
        point: Vec,
        approach: Vec,
        yaw_rad: float,
        ignore: set[int],
        gripper: float,
        seed: Vec,
    ) -> tuple[Vec, Vec, Vec] | None:
        """Joint angles at ``point + approach``, orientation and base adjustment for a
        top-down motion down to ``point``, over the four headings equivalent for a box-like
        object (or a held one)."""
        rotations = [top_down_rotation(yaw_rad + k * math.pi / 2) for k in range(4)]
        return self.arm.plan(point, approach, rotations, ignore, gripper, seed)

    def _plan_grasp(self, obj: str, kind: ObjectKind) -> tuple[Vec, Vec, Vec, Vec] | None:
        """Pre-grasp posture, hand orientation, UAV move and grasp point: the first of the
        object's grasp points the hand reaches touching nothing else, else the best one."""
        loop = self.loop
        lo, hi = object_bounds(loop.model, loop.data, obj, solid_only=True)
        body = loop.data.body(obj)
        rot = body.xmat.reshape(3, 3)
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        ignore = self.arm.body_geoms(obj)
        fallback = None
        for cand in grasp_points(kind, np.array(body.xpos), yaw, lo, hi):
            approach = np.array([0.0, 0.0, PRE_GRASP])
            sol = self.arm.plan(
                cand.point,
                approach,
                cand.rotations,
                ignore,
                c.GRIPPER_OPEN,
                np.asarray(TOP_DOWN_SEED),
            )
            if sol is None:
                continue
            q_pre, hand, shift = sol
            if not self.arm.ik.collisions(loop.data, q_pre, ignore, c.GRIPPER_OPEN, shift):
                return q_pre, hand, shift, cand.point
            fallback = fallback or (q_pre, hand, shift, cand.point)
        return fallback

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        return self.arm.touching_fingers(obj)

    def pick(self, episode: Episode, step: ArmStep) -> str | None:
        """Top-down grasp of ``step.object``; ``None`` on success, else the reason."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return f"unknown object {obj!r}"
        if loop.held is not None:
            return f"already holding {loop.held}"
        if not object_kind(kinds[obj]).graspable:
            return f"{obj} cannot be grasped"
        sol = self._plan_grasp(obj, object_kind(kinds[obj]))
        if sol is None:
            return f"{obj} is out of reach"
        q_pre, rot, shift, grasp = sol
        above = grasp + np.array([0.0, 0.0, PRE_GRASP])
        arm = self.arm
        arm.shift_base(shift)
        joint_move(loop, q_pre, 2.5, c.GRIPPER_OPEN)
        hold_with_gripper(loop, 0.3, c.GRIPPER_OPEN)
        if not arm.line(above, grasp, rot, 1.5, c.GRIPPER_OPEN):
            return f"{obj} is out of reach"
        hold_with_gripper(loop, 0.3, c.GRIPPER_OPEN)
        hold_with_gripper(loop, 1.0, c.GRIPPER_CLOSED)
        z0 = float(loop.data.body(obj).xpos[2])
        if not arm.line(grasp, grasp + np.array([0.0, 0.0, LIFT]), rot, 1.5, c.GRIPPER_CLOSED):
            return "cannot lift: out of reach"
        hold_with_gripper(loop, 0.3, c.GRIPPER_CLOSED)
        if not self.touching_fingers(obj) or loop.data.body(obj).xpos[2] - z0 < MIN_LIFT:
            return f"grasp of {obj} failed"
        loop.held = obj
        arm.shift_base(-shift)
        return None

    def place(self, episode: Episode, step: ArmStep) -> str | None:
        """Lower the held object onto/into ``step.object`` and release it."""
        loop, dest = self.loop, step.object
        held = loop.held
        if held is None:
            return "nothing held"
        if dest not in episode.object_ids():
            return f"unknown object {dest!r}"
        if not self.touching_fingers(held):
            loop.held = None
            return f"{held} slipped from the gripper"
        release = self._release_point(episode, held, dest)
        arm = self.arm
        tcp, rot = arm.tcp()
        clearance = max(0.0, self._top_under(dest) - (release[2] - self._hang(held))) + 0.05
        above = release + np.array([0.0, 0.0, clearance])
        heading = math.atan2(rot[1, 0], rot[0, 0])
        lift_to = np.array([tcp[0], tcp[1], max(tcp[2], above[2])])
        if not arm.line(tcp, lift_to, top_down_rotation(heading), 0.8, c.GRIPPER_CLOSED):
            return "cannot lift the held object"
        ignore = arm.body_geoms(held)
        sol = self._plan_top_down(
            release,
            above - release,
            heading,
            ignore,
            c.GRIPPER_CLOSED,
            arm_qpos(loop.model, loop.data),
        )
        if sol is None:
            return f"{dest} is out of reach"
        q_above, rot, shift = sol
        arm.shift_base(shift)
        joint_move(loop, q_above, 2.0, c.GRIPPER_CLOSED)
        if not arm.line(above, release, rot, 1.2, c.GRIPPER_CLOSED):
            return f"{dest} is out of reach"
        hold_with_gripper(loop, 0.6, c.GRIPPER_OPEN)
        loop.held = None
        arm.line(release, release + np.array([0.0, 0.0, 0.12]), rot, 1.0, c.GRIPPER_OPEN)
        stow_arm(loop, loop.config.flight)
        arm.shift_base(-shift)
        return None

    def _hang(self, held: str) -> float:
        """TCP height above the held object's bottom (m)."""
        lo, _ = object_bounds(self.loop.model, self.loop.data, held, solid_only=True)
        return float(self.loop.data.site(c.TCP_SITE).xpos[2] - lo[2])

    def _top_under(self, dest: str) -> float:
        """Top of the destination (m)."""
        _, hi = object_bounds(self.loop.model, self.loop.data, dest, solid_only=True)
        return float(hi[2])

    def _release_point(self, episode: Episode, held: str, dest: str) -> Vec:
        """TCP position that sets the held object down 2 cm above its resting place."""
        loop = self.loop
        lo, hi = object_bounds(loop.model, loop.data, dest, solid_only=True)
        centre = (lo + hi) / 2
        kinds = {o.id: object_kind(o.kind) for o in episode.objects}
        kind = kinds.get(dest)
        if kind is not None and kind.container and not kind.support:
            rest = float(lo[2]) + CONTAINER_FLOOR
        elif kind is None:  # a drawer: its floor is the body origin's height
            rest = float(loop.data.body(dest).xpos[2])
        else:
            rest = float(hi[2])
        x, y = self._into_band(centre, lo, hi, held)
        return np.array([x, y, rest + self._hang(held) + 0.02])

    def _into_band(self, centre: Vec, lo: Vec, hi: Vec, held: str) -> tuple[float, float]:
        """Release x, y: the destination's centre, moved away from the arm base (within the
        destination's footprint, the held object kept inside) when the centre lies closer than
        the inner edge of the top-down workspace."""
        base = self.loop.data.body(c.ARM_BASE_BODY).xpos
        offset = centre[:2] - base[:2]
        dist = float(np.linalg.norm(offset))
        if dist >= INNER_REACH or dist < 1e-6:
            return float(centre[0]), float(centre[1])
        hlo, hhi = object_bounds(self.loop.model, self.loop.data, held, solid_only=True)
        held_half = float(np.max(hhi[:2] - hlo[:2])) / 2
        slack = max(0.0, float(np.min(hi[:2] - lo[:2])) / 2 - held_half - 0.02)
        shift = min(slack, INNER_REACH - dist)
        x, y = centre[:2] + offset / dist * shift
        return float(x), float(y)


def grasp_skills(loop: SimLoop, arm: Arm | None = None) -> dict[str, ArmSkill]:
    """``pick`` and ``place`` bound to one loop (they share what is held)."""
    grasper = Grasper(loop, arm)
    return {
        "pick": lambda _loop, episode, step: grasper.pick(episode, step),
        "place": lambda _loop, episode, step: grasper.place(episode, step),
    }
