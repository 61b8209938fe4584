"""Stowing the arm by a way clear of the scene, the UAV climbing first where none is."""

from __future__ import annotations

import numpy as np

from vlm_bench.executor.motion.arm_core import ArmCore
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.flight_clearance import CLIMBS, FlightClearance
from vlm_bench.executor.motion.joint_moves import joint_move
from vlm_bench.executor.motion.uav_moves import STOWED_TOL, shift_base, stow_arm
from vlm_bench.sim.constants import ARM_STOW
from vlm_bench.sim.robot import arm_qpos, gripper_target
from vlm_bench.types.base import FloatArray

STOW_CLEARANCE = 0.05  # m the stow's planned way keeps from everything, or the UAV climbs


def stow_clear(core: ArmCore, flight: FlightClearance) -> FloatArray:
    """Stow the arm (:func:`stow_arm`) by a way clear of the UAV and, by
    :data:`STOW_CLEARANCE`, of everything else: straight in joint space, or through one of
    :func:`stow_vias` (straight, the wrist of an arm reaching out sideways can swing through
    the UAV's body), with the UAV first climbing the least of :data:`CLIMBS` where none is
    clear from here (the 18 kg arm folding up fast sways the UAV, so the way needs a margin
    beyond the plan). Where no way is clear, the straight one. Returns the climb made (m,
    world), for the skill to undo with its own UAV moves."""
    loop = core.loop
    now = arm_qpos(loop.model, loop.data)
    goal = np.asarray(ARM_STOW, dtype=np.float64)
    if float(np.max(np.abs(now - goal))) < STOWED_TOL:
        stow_arm(loop, loop.config.flight)
        return np.zeros(3)
    grip = gripper_target(loop.model, loop.data)

    def clear(way: list[FloatArray], base: BaseMove) -> bool:
        legs = zip([now, *way[:-1]], way, strict=True)
        query = CollisionQuery.of(set(), grip, base, None, STOW_CLEARANCE)
        return not any(core.path_hits(a, b, query, limit=0) for a, b in legs)

    for climb in (np.zeros(3), *CLIMBS):
        if climb.any() and not flight.flight_clear(climb):
            continue
        for way in ([goal], *([via, goal] for via in stow_vias(now, goal))):
            if clear(way, BaseMove(climb)):
                shift_base(loop, BaseMove(climb))
                for q in way[:-1]:
                    joint_move(loop, q, loop.config.flight.stow_s)
                stow_arm(loop, loop.config.flight)
                return climb
    stow_arm(loop, loop.config.flight)
    return np.zeros(3)


def stow_vias(now: FloatArray, goal: FloatArray) -> list[FloatArray]:
    """Postures to stow through: the wrist folded first, the base joint turned last, or the
    base joint turned first."""
    wrist = now.copy()
    wrist[4:] = goal[4:]
    fold = goal.copy()
    fold[0] = now[0]
    turn = now.copy()
    turn[0] = goal[0]
    return [wrist, fold, turn]
