"""Scripted skills on articulated parts: ``pull`` and ``close`` a drawer, ``rotate`` a knob.

Drawers: the open hand approaches the bar handle from the front (approach axis into the
drawer, fingers closing vertically around the bar), closes on it, and slides it along the
drawer's axis — by the arm where it reaches, then by the UAV carrying the hand the rest of the
way — before letting go, backing off and flying back. ``pull`` opens to ``PULL_TO``
(docs/design.md#arm-skills: ≥ 0.35 m), ``close`` pushes home.

Knobs: a top-down grasp of the knob's grip, then the hand turns about the vertical by
``TURN_DEG`` (docs/design.md#arm-skills: ≥ 90°) with the TCP kept in place, and lets go.

Each succeeds only if the part really moved that far (its joint is read from the simulation).
"""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.executor.motion.arm_core import IK_OK
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.ik import TOP_DOWN_SEED, frontal_rotation, top_down_rotation
from vlm_bench.executor.motion.joint_moves import hold_with_gripper, joint_move
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.hand import HANDLE_BACK_OFF, Hand
from vlm_bench.sim.constants import (
    ARM_BASE_BODY,
    CONTROL_DT,
    GRIPPER_CLOSED,
    GRIPPER_OPEN,
    part_handle_site,
    part_joint,
)
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode, PartRef
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep

PULL_TO = 0.38  # m: drawer opening a pull aims for (travel 0.40; docs/design.md#arm-skills: ≥ 0.35)
PULL_MIN = 0.35  # m: a pull counts from this opening
CLOSED_MAX = 0.02  # m: a close counts below this opening
PRE_HANDLE = 0.10  # m in front of the handle where the straight approach starts
SLIDE_SPEED = 0.10  # m/s
TURN_DEG = 115.0  # knob turn commanded (design.md#arm-skills: ≥ 90°; the grip slips 10-16°)
TURN_MIN_DEG = 90.0
KNOB_GRIP_DEPTH = 0.022  # m below the knob's top where the fingers hold it
TURN_S = 3.0  # s for the turn
CLEAR_OF_HANDLE = 0.50  # m: the open hand backs off the handle at least HANDLE_BACK_OFF and
# until the arm base is this far (horizontally) from it
STROKE_FRACTIONS = (1.0, 0.75, 0.5, 0.25)  # of a slide, tried for the arm's own stroke
BACK_ASSIST = (0.0, 0.1, 0.2)  # m the UAV may back away from a handle before grasping it
STROKE_JOINT_SPEED = 1.0  # rad/s: the fastest joint an arm's own slide may need


class _PartSkills:
    """What the skills on articulated parts share: the hand and the parts' joints."""

    def __init__(self, hand: Hand) -> None:
        self.hand = hand
        self.loop = hand.loop

    def part(self, episode: Episode, name: str, kind: str) -> PartRef | SkillFailure:
        """The part, or the reason the step cannot act on it."""
        parts = {p.id: p for p in episode.parts}
        if name not in parts:
            if name in episode.object_ids():
                return SkillFailure(FailureCode.WRONG_PART, f"{name} has no {kind} to act on")
            return SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {name!r}")
        part = parts[name]
        if part.kind != kind:
            return SkillFailure(FailureCode.WRONG_PART, f"{name} is a {part.kind}, not a {kind}")
        if self.loop.held is not None:
            return SkillFailure(
                FailureCode.BUSY_HAND, f"cannot operate {name} while holding {self.loop.held}"
            )
        return part

    def joint(self, part: str) -> float:
        """The part's joint position now (m for a drawer, rad for a knob)."""
        model, data = self.loop.model, self.loop.data
        return float(data.qpos[model.joint(part_joint(part)).qposadr[0]])


class Drawers(_PartSkills):
    """``pull`` and ``close`` for one scene."""

    def _handle(self, part: PartRef) -> tuple[FloatArray, FloatArray]:
        """The handle's grasp point and the drawer's outward axis (horizontal, world)."""
        point = np.array(self.loop.data.site(part_handle_site(part.id)).xpos)
        return point, self.hand.outward_axis(part.parent)

    def _handle_geoms(self, part: PartRef) -> set[int]:
        """The drawer's bar handle and its posts: all the hand may touch of it."""
        model = self.loop.model
        return {g for g in self.hand.body_geoms(part.id) if "handle" in (model.geom(g).name or "")}

    def _grasp_handle(self, part: PartRef) -> tuple[BaseMove, FloatArray] | SkillFailure:
        """Grasp the drawer's bar handle from the front; the UAV's move and the hand's
        orientation on success, else the reason."""
        hand, loop = self.hand, self.loop
        point, axis = self._handle(part)
        rotations = [frontal_rotation(axis, up) for up in (True, False)]
        drawer = hand.body_geoms(part.id)
        ignore = self._handle_geoms(part)  # the way in must clear the drawer's front
        assists = [
            BaseMove(np.append(axis[:2] * b, dz)) for b in BACK_ASSIST for dz in (0.0, -0.1, 0.1)
        ]
        sol = hand.planner.plan(
            point,
            axis * PRE_HANDLE,
            rotations,
            ignore,
            GRIPPER_OPEN,
            np.asarray(TOP_DOWN_SEED),
            assist=assists,
        )
        if sol is None or (
            sol.hits
            and hand.core.collisions(
                sol.q_start, CollisionQuery.of(ignore, GRIPPER_OPEN, sol.shift)
            )
        ):
            return SkillFailure(
                FailureCode.OUT_OF_REACH, f"the handle of {part.id} is out of reach"
            )
        rot, shift = sol.rotation, sol.shift
        hand.shift_base(shift)
        joint_move(loop, sol.q_start, 2.5, GRIPPER_OPEN)
        point, axis = self._handle(part)
        if not hand.lines.line(point + axis * PRE_HANDLE, point, rot, 1.5, GRIPPER_OPEN, sol.q_end):
            self._let_go(axis, shift)
            return SkillFailure(
                FailureCode.OUT_OF_REACH, f"the handle of {part.id} is out of reach"
            )
        hold_with_gripper(loop, 0.8, GRIPPER_CLOSED)
        if not hand.touching(drawer):
            self._let_go(axis, shift)
            return SkillFailure(
                FailureCode.GRASP_FAILED, f"grasp of the handle of {part.id} failed"
            )
        return shift, rot

    def _slide(self, part: PartRef, rot: FloatArray, distance: float) -> FloatArray:
        """Move the grasped handle ``distance`` along the drawer's outward axis (negative:
        inwards): by the arm as far as IK follows, then by the UAV; returns the UAV's move."""
        hand = self.hand
        start, axis = self._handle(part)
        end = start + axis * distance
        reach = self._stroke(part, start, axis * distance, rot)
        if reach is not None:
            hand.lines.line(start, reach, rot, _slide_seconds(reach - start), GRIPPER_CLOSED)
        rest = float(np.dot(end - hand.tcp()[0], axis * math.copysign(1.0, distance)))
        if rest > 0.01:
            step = axis * math.copysign(rest, distance)
            hand.carry(step, SLIDE_SPEED)
            return step
        return np.zeros(3)

    def _stroke(
        self, part: PartRef, start: FloatArray, travel: FloatArray, rot: FloatArray
    ) -> FloatArray | None:
        """The end of the longest part of the slide (all, ¾, ½ or ¼ of ``travel``) the arm
        makes on its own: where IK follows the whole line (previewed step by step) with no
        joint faster than :data:`STROKE_JOINT_SPEED`, none within :data:`MIN_MARGIN` of its
        limit, and nothing but the handle touched. Near its limits a long pull whips the base
        joint round and twists the bar out of the fingers, or folds the elbow into the
        drawer's front. ``None``: the UAV carries the whole slide."""
        hand = self.hand
        handle = self._handle_geoms(part)
        for frac in STROKE_FRACTIONS:
            end = start + travel * frac
            seconds = _slide_seconds(end - start)
            postures = hand.lines.steady_line(start, end, rot, seconds, STROKE_JOINT_SPEED)
            if postures is None:
                continue
            checked = [*postures[:: max(1, len(postures) // 8)], postures[-1]]
            query = CollisionQuery.of(handle, GRIPPER_CLOSED, BaseMove.still())
            if any(hand.core.collisions(p, query) for p in checked):
                continue
            return end
        return None

    def _let_go(self, axis: FloatArray, back: BaseMove, return_xy: bool = True) -> None:
        """Open, back the hand off along ``axis`` until the stowed arm clears the handle (the
        UAV carries it: the arm is usually folded as far as it goes), stow, and undo the UAV's
        moves (``back`` and the retreat; only their vertical part unless ``return_xy``: flying
        back to where a drawer was pulled from would run the stowed arm into it)."""
        loop, hand = self.loop, self.hand
        hold_with_gripper(loop, 0.5, GRIPPER_OPEN)
        base = loop.data.body(ARM_BASE_BODY).xpos
        tcp, _ = hand.tcp()
        gap = float(np.dot(base[:2] - tcp[:2], axis[:2]))
        retreat = axis * max(HANDLE_BACK_OFF, CLEAR_OF_HANDLE - gap)
        hand.carry(retreat, SLIDE_SPEED)
        undo = -(back.xyz + retreat + hand.stow())
        hand.shift_base(
            BaseMove(undo, -back.yaw) if return_xy else BaseMove.vertical(float(undo[2]))
        )

    def _move_drawer(self, episode: Episode, step: ArmStep, opening: float) -> SkillFailure | None:
        """Grasp the drawer's handle, slide it to ``opening`` (m) and let go."""
        part = self.part(episode, step.object, "drawer")
        if isinstance(part, SkillFailure):
            return part
        grasp = self._grasp_handle(part)
        if isinstance(grasp, SkillFailure):
            return grasp
        shift, rot = grasp
        _, axis = self._handle(part)
        carried = self._slide(part, rot, opening - self.joint(part.id))
        self._let_go(axis, shift.plus(carried), return_xy=opening < self.joint(part.id))
        return None

    def pull(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Open the drawer ``step.object`` to ``PULL_TO``; ``None`` on success."""
        reason = self._move_drawer(episode, step, PULL_TO)
        if reason is None and self.joint(step.object) < PULL_MIN:
            return SkillFailure(
                FailureCode.ARTICULATION_SHORT,
                f"{step.object} opened only {self.joint(step.object):.2f} m",
            )
        return reason

    def close(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Push the drawer ``step.object`` shut; ``None`` on success."""
        reason = self._move_drawer(episode, step, -0.01)
        if reason is None and self.joint(step.object) > CLOSED_MAX:
            return SkillFailure(
                FailureCode.ARTICULATION_SHORT,
                f"{step.object} is still {self.joint(step.object):.2f} m open",
            )
        return reason


class Knobs(_PartSkills):
    """``rotate`` for one scene."""

    def rotate(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Turn the knob ``step.object`` by ``TURN_DEG``; ``None`` on success."""
        part = self.part(episode, step.object, "knob")
        if isinstance(part, SkillFailure):
            return part
        loop, hand = self.loop, self.hand
        site = np.array(loop.data.site(part_handle_site(part.id)).xpos)
        knob_top = float(loop.data.body(part.id).xpos[2]) + 0.045
        grip = np.array([site[0], site[1], knob_top - KNOB_GRIP_DEPTH])
        plan = self._plan_turn(part, grip)
        if plan is None:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{part.id} is out of reach")
        q_pre, heading, shift = plan
        ignore = hand.body_geoms(part.id)
        hand.shift_base(shift)
        joint_move(loop, q_pre, 2.5, GRIPPER_OPEN)
        rot = top_down_rotation(heading)
        above = grip + np.array([0.0, 0.0, PRE_HANDLE])
        if not hand.lines.line(above, grip, rot, 1.5, GRIPPER_OPEN):
            hand.shift_base(BaseMove(-shift.xyz - hand.stow(), -shift.yaw))
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{part.id} is out of reach")
        hold_with_gripper(loop, 1.0, GRIPPER_CLOSED)
        start = self.joint(part.id)
        if hand.touching(ignore):
            self._turn(grip, heading, math.radians(TURN_DEG))
        turned = math.degrees(self.joint(part.id) - start)
        hold_with_gripper(loop, 0.5, GRIPPER_OPEN)
        hand.lines.line(grip, above, rot, 1.0, GRIPPER_OPEN)
        hand.shift_base(BaseMove(-shift.xyz - hand.stow(), -shift.yaw))
        if turned < TURN_MIN_DEG:
            return SkillFailure(
                FailureCode.ARTICULATION_SHORT, f"{part.id} turned only {turned:.0f}°"
            )
        return None

    def _plan_turn(
        self, part: PartRef, grip: FloatArray
    ) -> tuple[FloatArray, float, BaseMove] | None:
        """Pre-grasp posture, start heading and UAV move from which the hand reaches the grip
        at the start and at the end of the turn, touching nothing but the knob, also on the
        joint-space way from the stowed arm to the pre-grasp posture. The UAV moves are the
        reach planner's assists: a knob the stand-off leaves close under the arm base is
        reached after a small horizontal move away from it, as a grasp is."""
        hand, data = self.hand, self.loop.data
        ignore = hand.body_geoms(part.id)
        turn = math.radians(TURN_DEG)
        best: tuple[float, tuple[FloatArray, float, BaseMove]] | None = None
        now = arm_qpos(self.loop.model, data)
        for shift in hand.planner.assists(grip):
            query = CollisionQuery.of(ignore, GRIPPER_OPEN, shift)
            for k in range(8):
                heading = -math.pi + k * math.pi / 4
                rot0, rot1 = top_down_rotation(heading), top_down_rotation(heading + turn)
                q0, res0 = hand.core.solve_any(grip, rot0, np.asarray(TOP_DOWN_SEED), shift)
                if res0 > IK_OK or hand.core.collisions(q0, query):
                    continue
                q1, res1 = hand.core.ik.solve(data, grip, rot1, q0, base=shift)
                if res1 > IK_OK or abs(float(q1[6] - q0[6])) < 0.8 * turn:
                    continue
                above = grip + np.array([0.0, 0.0, PRE_HANDLE])
                q_pre, res = hand.core.ik.solve(data, above, rot0, q0, base=shift)
                if res > IK_OK or hand.core.path_hits(now, q_pre, query, limit=0):
                    continue
                margin = hand.core.ik.limit_margin(q1)
                if best is None or margin > best[0]:
                    best = (margin, (q_pre, heading, shift))
            if best is not None:
                return best[1]
        return None

    def _turn(self, grip: FloatArray, heading: float, turn: float) -> None:
        """Turn the closed hand about the vertical through ``grip`` by ``turn`` rad."""
        n = max(2, round(TURN_S / CONTROL_DT))
        poses = ((grip, top_down_rotation(heading + turn * i / n)) for i in range(1, n + 1))
        if self.hand.lines.follow(poses, GRIPPER_CLOSED):
            self.loop.hold(0.3)


def _slide_seconds(travel: FloatArray) -> float:
    """Duration (s) of the arm's own slide over ``travel`` (m)."""
    return max(1.5, float(np.linalg.norm(travel)) / SLIDE_SPEED)


def articulation_skills(loop: SimLoop, hand: Hand | None = None) -> dict[str, Skill]:
    """``pull``, ``close`` and ``rotate`` bound to one loop."""
    hand = hand or Hand(loop)
    drawers, knobs = Drawers(hand), Knobs(hand)
    return {"pull": drawers.pull, "close": drawers.close, "rotate": knobs.rotate}
