"""Scripted top-down ``pick`` and ``place`` with IK and real contact physics (no welds).

Pick: open, move (joint-space, minimum-jerk) to a pre-grasp 0.12 m above the object with the
hand pointing down, descend along a straight line, close, lift 0.15 m. It succeeds only if both
fingers touch the object and the object has risen. Place (:mod:`.placing`): move above the
destination, lower, open, retreat up and stow.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.motion.arm_planner import Reach
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.ik import TOP_DOWN_SEED
from vlm_bench.executor.motion.joint_moves import hold_with_gripper, joint_move
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.carry_raise import raise_to_carry
from vlm_bench.executor.skills.grasp_points import GraspPoint, grasp_points
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.placing import Placer
from vlm_bench.sim.constants import GRIPPER_CLOSED, GRIPPER_OPEN
from vlm_bench.sim.objects.bounds import geom_bounds, object_bounds, subtree_geoms
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.world import ObjectKind

PRE_GRASP = 0.12  # m above the grasp point
LIFT = 0.15  # m
MIN_LIFT = 0.08  # m the object must rise for a pick to count
SECTION_HALF = 0.025  # m along the hand: geoms centred this near make the grasped section
GRASP_DESCENT = 1.5  # s: the hand's straight way down onto a grasp point
GRASP_TURN_ROOM = 0.15  # rad: a grasp posture with the base joint nearer its limit counts as a
# contact: the lift and raise take the joint closer still, and a place beside needs room to turn
GraspOrder = Callable[[list[GraspPoint]], list[GraspPoint]]
"""Reorders an object's candidate grasps before the first reachable one is taken (varied
demonstrations, vlm_bench/vla/demos/variation.py)."""


class Picker:
    """``pick`` for one scene (what is held lives in ``loop.held``)."""

    def __init__(self, hand: Hand, order: GraspOrder | None = None) -> None:
        self.hand = hand
        self.loop = hand.loop
        self.order = order

    def pick(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Top-down grasp of ``step.object``; ``None`` on success, else the failure."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {obj!r}")
        if loop.held is not None:
            return SkillFailure(FailureCode.ALREADY_HOLDING, f"already holding {loop.held}")
        if not object_kind(kinds[obj]).graspable:
            return SkillFailure(FailureCode.NOT_GRASPABLE, f"{obj} cannot be grasped")
        sol = self.plan_grasp(obj, object_kind(kinds[obj]))
        if sol is None:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{obj} is out of reach")
        return self._grasp(obj, *sol)

    def _grasp(self, obj: str, reach: Reach, grasp: FloatArray) -> SkillFailure | None:
        """Make the planned ``reach`` down to ``grasp``, close, lift and check the hold."""
        loop, hand = self.loop, self.hand
        rot, shift = reach.rotation, reach.shift
        above = grasp + np.array([0.0, 0.0, PRE_GRASP])
        hand.shift_base(shift)
        joint_move(loop, reach.q_start, 2.5, GRIPPER_OPEN)
        hold_with_gripper(loop, 0.3, GRIPPER_OPEN)
        if not hand.lines.line(above, grasp, rot, GRASP_DESCENT, GRIPPER_OPEN, reach.q_end):
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{obj} is out of reach")
        hold_with_gripper(loop, 0.3, GRIPPER_OPEN)
        hold_with_gripper(loop, 1.0, GRIPPER_CLOSED)
        z0 = float(loop.data.body(obj).xpos[2])
        bottom = self._bottom(obj)
        lifted = grasp + np.array([0.0, 0.0, LIFT])
        if not hand.lines.line(grasp, lifted, rot, 1.5, GRIPPER_CLOSED):
            return SkillFailure(FailureCode.OUT_OF_REACH, "cannot lift: out of reach")
        hold_with_gripper(loop, 0.3, GRIPPER_CLOSED)
        if not hand.touching_fingers(obj) or loop.data.body(obj).xpos[2] - z0 < MIN_LIFT:
            return SkillFailure(FailureCode.GRASP_FAILED, f"grasp of {obj} failed")
        loop.held = obj
        raise_to_carry(hand, rot, GRIPPER_CLOSED)
        # Undo the UAV's move, but a climb only as far as the held object stays MIN_LIFT
        # above where it lay (the arm may be unable to raise it further), and not at all
        # where the way down is not clear.
        undo = -shift.xyz
        undo[2] = max(undo[2], min(0.0, bottom + MIN_LIFT - self._bottom(obj)))
        turn = hand.flight.clear_for_flight(undo) if undo[2] < 0.0 else 0.0
        if turn is None:
            undo[2] = 0.0
        hand.shift_base(BaseMove(undo, -shift.yaw))
        hand.flight.turn_back(turn)
        return None

    def plan_grasp(self, obj: str, kind: ObjectKind) -> tuple[Reach, FloatArray] | None:
        """The descent onto a grasp point, and the point: the first of the object's grasp
        points the hand reaches touching nothing else, else the best one."""
        loop = self.loop
        lo, hi = object_bounds(loop.model, loop.data, obj, solid_only=True)
        body = loop.data.body(obj)
        rot = body.xmat.reshape(3, 3)
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        ignore = self.hand.body_geoms(obj)
        com = np.array(body.xipos)
        candidates = grasp_points(kind, np.array(body.xpos), yaw, lo, hi, com)
        ordered = self.order(candidates) if self.order else candidates
        points = [
            (
                self.on_section(obj, cand.point, cand.rotations[0])
                if cand.centre_across
                else cand.point,
                cand.rotations,
            )
            for cand in ordered
        ]
        # Every point's clear descent is looked for before any point's contacts are counted:
        # counting them is most of a search, and only the fallback needs them.
        for max_hits in (0, math.inf):
            for point, rotations in points:
                sol = self.hand.planner.plan(
                    point,
                    np.array([0.0, 0.0, PRE_GRASP]),
                    rotations,
                    ignore,
                    GRIPPER_OPEN,
                    np.asarray(TOP_DOWN_SEED),
                    line=GRASP_DESCENT,
                    turn_room=GRASP_TURN_ROOM,
                    max_hits=max_hits,
                )
                if sol is not None:
                    return sol, point
        return None

    def on_section(self, obj: str, point: FloatArray, rotation: FloatArray) -> FloatArray:
        """``point`` moved across (along the hand's closing axis, ``rotation``'s y) to the
        middle of ``obj``'s solid cross-section between the fingers: of its collision geoms
        centred within :data:`SECTION_HALF` of the point along the hand's x axis."""
        model, data = self.loop.model, self.loop.data
        along, across = rotation[:, 0].copy(), rotation[:, 1].copy()
        along[2] = across[2] = 0.0
        lo, hi = math.inf, -math.inf
        for g in subtree_geoms(model, model.body(obj).id, solid_only=True):
            glo, ghi = geom_bounds(model, data, g)
            mid, half = (glo + ghi) / 2, (ghi - glo) / 2
            if abs(float(np.dot(mid - point, along))) > SECTION_HALF:
                continue
            off, h = float(np.dot(mid - point, across)), float(np.dot(half, np.abs(across)))
            lo, hi = min(lo, off - h), max(hi, off + h)
        if lo > hi:
            return point
        return point + across * (lo + hi) / 2

    def _bottom(self, obj: str) -> float:
        """Height of ``obj``'s lowest solid point (m)."""
        lo, _ = object_bounds(self.loop.model, self.loop.data, obj, solid_only=True)
        return float(lo[2])


def grasp_skills(
    loop: SimLoop, hand: Hand | None = None, order: GraspOrder | None = None
) -> dict[str, Skill]:
    """``pick`` and ``place`` bound to one loop (they share one hand and what it holds);
    ``order`` reorders each pick's candidate grasps (default: best first)."""
    hand = hand or Hand(loop)
    return {"pick": Picker(hand, order).pick, "place": Placer(hand).place}
