"""Scripted top-down ``place``: carry the held object over its destination, lower it in joint
space on the path the plan checked, let go, retreat and stow."""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.executor.motion.arm_planner import Reach
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.flight_clearance import FLIGHT_CLEARANCE
from vlm_bench.executor.motion.ik import top_down_rotation
from vlm_bench.executor.motion.joint_moves import HELD_JOINT_SPEED, hold_with_gripper, joint_move
from vlm_bench.executor.skills.carry_raise import raise_to_carry
from vlm_bench.executor.skills.hand import RELEASE_RISE, Hand
from vlm_bench.executor.skills.place_descents import PLACE_CLEARANCE, Descents, Drop
from vlm_bench.executor.skills.release_points import (
    hang,
    kind_of,
    release_point,
    top_of,
)
from vlm_bench.sim.constants import ARM_BASE_BODY, GRIPPER_CLOSED, GRIPPER_OPEN
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep

TALL = 2.0  # height over the narrowest side of the base: such an object is set down, not dropped
SET_DOWN = 0.04  # m the hand lowers a tall object at most, from its release, to set it down
SET_DOWN_STEP = 0.005  # m the hand lowers it per 0.1 s until it touches
CENTRE_TOL = 0.001  # m: a tall object's middle is brought this close over its resting place...
CENTRE_TRIES = 3  # ...in at most this many sideways moves of the hand, before it is set down
GLIDE_SPEED = 0.1  # m/s: mean speed of the glide over a release; it turns the hand as it goes,
# and an object gripped by its top few mm (a flat nut) creeps along the pads at 0.15 m/s
WIDE_HANG = 0.04  # m: an object whose centre of mass hangs this far off the TCP glides over
# its release keeping the hand's heading where it can (turning, it pries the fingers open)
SLIP = 0.03  # m a held object may move in the hand on the way to its release while out of one
# finger's touch (an object set down on its destination can be pushed up between the pads)
LIFT_SECONDS = 0.8  # s the hand takes to rise over its destination before a place
RELEASE_TOL = 0.06  # m: the TCP must come this close to the release point (more than an
# outstretched arm's sag: farther off, it did not get there)

Descent = tuple[FloatArray, FloatArray, FloatArray, BaseMove]
"""A descent's first and last postures, the hand's orientation and the UAV's move in all."""


class Placer:
    """``place`` for one scene (what is held lives in ``loop.held``)."""

    def __init__(self, hand: Hand) -> None:
        self.hand = hand
        self.loop = hand.loop
        self.ways = Descents(hand)

    def place(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        """Lower the held object onto/into ``step.object`` and release it."""
        loop, dest, hand = self.loop, step.object, self.hand
        held = loop.held
        if held is None:
            return SkillFailure(FailureCode.NOTHING_HELD, "nothing held")
        if dest not in episode.object_ids():
            return SkillFailure(FailureCode.UNKNOWN_OBJECT, f"unknown object {dest!r}")
        if not hand.touching_fingers(held):
            loop.held = None
            return SkillFailure(FailureCode.SLIPPED, f"{held} slipped from the gripper")
        release = release_point(hand, episode, held, dest)
        grip = self._in_hand(held)
        tcp, rot = hand.tcp()
        clearance = max(0.0, top_of(hand, dest) - (release[2] - hang(hand, held))) + 0.05
        above = release + np.array([0.0, 0.0, clearance])
        heading = math.atan2(rot[1, 0], rot[0, 0])
        lift_to = np.array([tcp[0], tcp[1], max(tcp[2], above[2])])
        if not self._lift(tcp, lift_to, top_down_rotation(heading), held):
            # The arm cannot raise it that far on its own (folded up under the base) or not
            # clear of the scene: the UAV climbs the rest, carrying it.
            hand.shift_base(BaseMove.vertical(max(0.0, lift_to[2] - hand.tcp()[0][2])))
        drop = Drop(held, dest, release, above, heading, hand.body_geoms(held))
        planned = self.ways.plan_release(episode, drop)
        if planned is None:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{dest} is out of reach")
        sol, drop = planned
        return self._release(episode, sol, drop, grip)

    def _lift(self, tcp: FloatArray, to: FloatArray, rot: FloatArray, held: str) -> bool:
        """Raise the hand straight from ``tcp`` to ``to`` where the arm's line, previewed,
        touches nothing but ``held``; whether it got there. An arm stretched far down folds
        up by swinging its elbow out, which can push what stands beside it (an open drawer
        shut under the release planned into it)."""
        hand = self.hand
        postures = hand.lines.preview_line(tcp, to, rot, LIFT_SECONDS)
        if postures is None:
            return False
        query = CollisionQuery.of(hand.body_geoms(held), GRIPPER_CLOSED, None, hand.core.carried())
        if hand.core.hits_at(postures, query, limit=0):
            return False
        return hand.lines.line(tcp, to, rot, LIFT_SECONDS, GRIPPER_CLOSED)

    def _release(
        self, episode: Episode, sol: Reach, drop: Drop, grip: FloatArray
    ) -> SkillFailure | None:
        """Fly ``sol``'s UAV move, bring the object over the release, lower it on the path the
        plan checked (in joint space: a long straight line into a deep drawer can leave IK's
        branch), let go and retreat; ``grip``: where the object sat in the hand before."""
        loop, hand, held, release = self.loop, self.hand, drop.held, drop.release
        hand.shift_base(sol.shift)
        q_start, q_end, rot, shift = self._bring_over(episode, drop, sol)
        joint_move(loop, q_start, 2.0, GRIPPER_CLOSED, HELD_JOINT_SPEED)
        joint_move(loop, q_end, 1.5, GRIPPER_CLOSED, HELD_JOINT_SPEED)
        hold_with_gripper(loop, 0.3, GRIPPER_CLOSED)
        moved = float(np.linalg.norm(self._in_hand(held) - grip))
        if moved > SLIP and not hand.touching_fingers(held):
            loop.held = None
            return SkillFailure(FailureCode.SLIPPED, f"{held} slipped from the gripper")
        if float(np.linalg.norm(hand.tcp()[0] - release)) > RELEASE_TOL:
            return SkillFailure(FailureCode.OUT_OF_REACH, f"{drop.dest} is out of reach")
        if _is_tall(episode, held):
            self._set_down(held, drop.dest, release, rot)
        hold_with_gripper(loop, 0.6, GRIPPER_OPEN)
        loop.held = None
        retreat = max(RELEASE_RISE, float(drop.above[2] - release[2]))  # clear of the rim
        hand.lines.line(release, release + np.array([0.0, 0.0, retreat]), rot, 1.0, GRIPPER_OPEN)
        raise_to_carry(hand, rot, GRIPPER_OPEN)
        undo = shift.undo()  # the UAV's moves (and turn) made for the release, undone
        hand.shift_base(BaseMove(undo.xyz - hand.stow(), undo.yaw))
        return None

    def _set_down(self, held: str, dest: str, release: FloatArray, rot: FloatArray) -> None:
        """Centre ``held`` over ``release`` (:meth:`_centre_over`), then lower the hand until
        ``held`` touches ``dest``, by at most :data:`SET_DOWN`: a tall object let go above a
        curved floor rocks and topples, and one lowered by a fixed amount is pushed up in the
        fingers where it already stands."""
        hand = self.hand
        ours, theirs = hand.body_geoms(held), hand.body_geoms(dest)
        step = np.array([0.0, 0.0, SET_DOWN_STEP])
        point = self._centre_over(held, release, rot)
        for _ in range(round(SET_DOWN / SET_DOWN_STEP)):
            if hand.in_contact(ours, theirs):
                return
            if not hand.lines.line(point, point - step, rot, 0.1, GRIPPER_CLOSED):
                return
            point = point - step

    def _centre_over(self, held: str, release: FloatArray, rot: FloatArray) -> FloatArray:
        """Move the hand sideways until ``held``'s middle is within :data:`CENTRE_TOL` over
        ``release`` (the resting place's centre); the TCP there. An object held off its middle
        (a bottle by its cap) hangs off the hand's centre, and the TCP stops a few mm off its
        goal, while a tall object's base may just fit the floor it is set on."""
        loop, hand = self.loop, self.hand
        tcp = hand.tcp()[0]
        for _ in range(CENTRE_TRIES):
            lo, hi = object_bounds(loop.model, loop.data, held, solid_only=True)
            off = release[:2] - (lo[:2] + hi[:2]) / 2
            if float(np.linalg.norm(off)) < CENTRE_TOL:
                break
            to = tcp + np.array([off[0], off[1], 0.0])
            if not hand.lines.line(tcp, to, rot, 0.3, GRIPPER_CLOSED):
                break
            hold_with_gripper(loop, 0.2, GRIPPER_CLOSED)  # let it stop swinging
            tcp = hand.tcp()[0]
        return tcp

    def _bring_over(self, episode: Episode, drop: Drop, sol: Reach) -> Descent:
        """Carry the held object to above its release, with the UAV moved by ``sol``'s shift
        already: the hand glides there pointing down (turning to the plan's heading on the
        way, or, where the arm would meet itself turning, keeping its own); else the UAV flies
        it there with the arm's posture held; else (the flight would touch something) nothing
        moves and the plan's joint-space move takes it. A joint-space move between two
        top-down postures tilts the hand midway and swings an object hanging from the fingers
        out of them."""
        hand, loop = self.hand, self.loop
        seconds = max(2.0, float(np.linalg.norm(drop.above - hand.tcp()[0])) / GLIDE_SPEED)
        now = arm_qpos(loop.model, loop.data)
        tall = _is_tall(episode, drop.held)
        level = tall or self._hangs_wide(drop.held)
        if (done := self._glide(drop, sol, sol.shift, seconds, level)) is not None:
            return done
        # The plan's heading failed: a plan for the hand's heading now.
        keep = hand.planner.plan(
            drop.release,
            drop.above - drop.release,
            [top_down_rotation(drop.heading)],
            drop.ignore,
            GRIPPER_CLOSED,
            now,
            [BaseMove.still()],
            PLACE_CLEARANCE,
            max_hits=0,
        )
        if (
            keep is not None
            and (done := self._glide(drop, keep, sol.shift, seconds, level)) is not None
        ):
            return done
        travel = drop.above - hand.tcp()[0]
        down = self.ways.descent(drop, BaseMove(travel))
        if down is not None and hand.flight.flight_clear(travel, clearance=FLIGHT_CLEARANCE):
            hand.shift_base(BaseMove(travel))
            # Planned again where the UAV settled: the hover is never exact.
            way = self.ways.descent(drop, BaseMove.still()) or down
            return way.q_start, way.q_end, way.rotation, sol.shift.plus(travel)
        return sol.q_start, sol.q_end, sol.rotation, sol.shift

    def _hangs_wide(self, held: str) -> bool:
        """Whether ``held``'s centre of mass lies more than :data:`WIDE_HANG` off the TCP
        horizontally (a bowl by its rim): turning the hand, it pries the fingers open."""
        off = np.array(self.loop.data.body(held).xipos) - self.hand.tcp()[0]
        return float(np.linalg.norm(off[:2])) > WIDE_HANG

    def _glide(
        self,
        drop: Drop,
        plan: Reach,
        shift: BaseMove,
        seconds: float,
        level: bool = False,
    ) -> Descent | None:
        """Glide the hand to above the release towards ``plan``'s start: in a straight line
        (``level``: keeping its heading, for an object hanging wide or tall) or, where that
        is refused and the object may turn, swinging round the arm base, turning with the
        swing to ``plan``'s heading; the descent from where it ends (another branch, maybe:
        planned again there), else ``None``."""
        lines, base = self.hand.lines, np.array(self.loop.data.body(ARM_BASE_BODY).xpos)
        ways = [(None, None)] if level else [(plan.rotation, None), (plan.rotation, base)]
        if not any(
            lines.glide(drop.above, rot, seconds, GRIPPER_CLOSED, plan.q_start, about)
            for rot, about in ways
        ):
            return None
        way = self.ways.descent(drop, BaseMove.still(), level) or plan
        return way.q_start, way.q_end, way.rotation, shift

    def _in_hand(self, obj: str) -> FloatArray:
        """Where ``obj`` is in the hand's frame (m)."""
        tcp, rot = self.hand.tcp()
        return rot.T @ (np.array(self.loop.data.body(obj).xpos) - tcp)


def _is_tall(episode: Episode, held: str) -> bool:
    """Whether ``held`` is :data:`TALL` (a bottle): it hangs from its top in the hand."""
    kind = kind_of(episode, held)
    return kind is not None and kind.size[2] > TALL * min(kind.size[:2])
