"""Raising the hand to its carrying height after a pick or a release."""

from __future__ import annotations

import numpy as np

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.joint_moves import HELD_JOINT_SPEED, joint_move
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.sim.constants import ARM_BASE_BODY
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray

CARRY_DEPTH = 0.30  # m below the arm base: a held object's TCP height in flight
CARRY_SPEED = 0.15  # m/s: mean speed of the empty hand's raise...
HELD_CARRY_SPEED = 0.1  # m/s: ...and of the raise holding an object, as a place's glide: a flat
# nut gripped by its top few mm creeps down the pads and falls out at 0.15 m/s
RAISE_JOINT_SPEED = 1.0  # rad/s: the fastest joint the straight raise to carry may need...
RAISE_MARGIN = 0.01  # rad: ...and the nearest it may come to its limit (0: at IK's clamp)
RAISE_SWING = 1.0  # rad: the widest joint swing of a joint-space raise with an object in hand:
# a wider swing tilts the hand and flings what it holds


def raise_to_carry(hand: Hand, rot: FloatArray, gripper: float) -> None:
    """Lift the hand straight up until the TCP is :data:`CARRY_DEPTH` below the arm base (or
    as high as the arm follows). Holding an object, UAV moves carry it there rather than
    stowed, where a bulky object would be folded against the arm and knocked out of the
    fingers; empty, the stow then starts clear of what the hand just let go of.

    Where the straight line leaves IK's branch or whips a joint round (an arm stretched far
    down folds up only by swinging its elbow): a checked joint-space move instead, from where
    it stopped; holding an object, only one no wider than :data:`RAISE_SWING`, else half the
    line, else none (it stays where the pick lifted it)."""
    loop = hand.loop
    tcp, _ = hand.tcp()
    top = float(loop.data.body(ARM_BASE_BODY).xpos[2]) - CARRY_DEPTH
    if tcp[2] >= top:
        return
    goal = np.array([tcp[0], tcp[1], top])
    if _raise(hand, tcp, goal, rot, gripper):
        return
    held = hand.body_geoms(loop.held) if loop.held is not None else set()
    now = arm_qpos(loop.model, loop.data)
    sol = hand.planner.plan(
        goal, np.zeros(3), [rot], held, gripper, now, [BaseMove.still()], max_hits=0
    )
    narrow = sol is not None and float(np.max(np.abs(sol.q_end - now))) <= RAISE_SWING
    if sol is not None and (loop.held is None or narrow):
        joint_move(loop, sol.q_end, 1.5, gripper, HELD_JOINT_SPEED)
        return
    if loop.held is not None:
        _raise(hand, tcp, (tcp + goal) / 2, rot, gripper)


def _raise(hand: Hand, tcp: FloatArray, goal: FloatArray, rot: FloatArray, gripper: float) -> bool:
    """The straight raise from ``tcp`` to ``goal`` at :data:`CARRY_SPEED` (holding an object,
    :data:`HELD_CARRY_SPEED`), where it is steady (holding one) and IK follows it; whether it
    got there."""
    speed = CARRY_SPEED if hand.loop.held is None else HELD_CARRY_SPEED
    seconds = max(1.0, float(goal[2] - tcp[2]) / speed)
    if hand.loop.held is not None and (
        hand.lines.steady_line(tcp, goal, rot, seconds, RAISE_JOINT_SPEED, RAISE_MARGIN) is None
    ):
        return False
    return hand.lines.line(tcp, goal, rot, seconds, gripper)
