"""Straight motions of the hand: TCP lines, glides and their offline previews.

A line is solved step by step by IK, one pose per control step (minimum-jerk timing); a
preview solves the same poses offline, so a caller can check a line (joint speeds, limits,
contacts) before it commands it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from vlm_bench.executor.motion.arm_core import IK_OK, MIN_MARGIN, ArmCore, spaced_postures
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.ik import top_down_rotation
from vlm_bench.executor.motion.joint_moves import min_jerk
from vlm_bench.sim.constants import CONTROL_DT
from vlm_bench.sim.robot import arm_qpos, set_arm_targets
from vlm_bench.types.base import FloatArray

GLIDE_MARGIN = 0.01  # rad: the nearest a glide may bring a joint to its limit (0: IK's clamp)


def steps(seconds: float) -> list[float]:
    """Minimum-jerk progress at each control step of a ``seconds``-long motion (at least 2)."""
    n = max(2, round(seconds / CONTROL_DT))
    return [min_jerk(i / n) for i in range(1, n + 1)]


def _bearing(point: FloatArray, about: FloatArray) -> tuple[float, float]:
    """``point``'s bearing (rad) and horizontal distance (m) from ``about``."""
    d = point[:2] - about[:2]
    return math.atan2(d[1], d[0]), float(np.linalg.norm(d))


def glide_turn(
    start: FloatArray, end: FloatArray, about: FloatArray | None, h0: float, h1: float | None
) -> float:
    """How far (rad) a glide from ``start`` to ``end`` turns the hand from heading ``h0`` to
    ``h1``: the least turn on a line; on an arc round ``about``, the swing's bearing change
    plus the least rest (the hand turns with the swing, as the base joint turns it). With
    ``h1`` ``None`` no rest: the hand keeps its heading to the swing (none on a line)."""
    sweep = 0.0
    if about is not None:
        sweep = math.remainder(_bearing(end, about)[0] - _bearing(start, about)[0], 2 * math.pi)
    return sweep + (0.0 if h1 is None else math.remainder(h1 - h0 - sweep, 2 * math.pi))


def arc_poses(
    start: FloatArray,
    end: FloatArray,
    about: FloatArray,
    h0: float,
    turn: float,
    progress: Sequence[float],
) -> list[tuple[FloatArray, FloatArray]]:
    """Top-down poses from ``start`` to ``end`` swinging round the vertical through
    ``about``: bearing, distance from that axis and height each change evenly with
    ``progress``, and the heading turns from ``h0`` by ``turn`` (rad). Round the arm base this
    is the base joint's own swing: a straight line from one side of the base to the other
    passes close under it, where the arm folds onto its limits."""
    b0, r0 = _bearing(start, about)
    b1, r1 = _bearing(end, about)
    sweep = math.remainder(b1 - b0, 2 * math.pi)
    poses = []
    for s in progress:
        b, r = b0 + sweep * s, r0 + (r1 - r0) * s
        height = start[2] + (end[2] - start[2]) * s
        point = np.array([about[0] + r * math.cos(b), about[1] + r * math.sin(b), height])
        poses.append((point, top_down_rotation(h0 + turn * s)))
    return poses


class ArmLines:
    """Straight TCP motions of one loop's arm.

    Args:
        core: The arm (IK, collision queries).
    """

    def __init__(self, core: ArmCore) -> None:
        self.core = core
        self.loop = core.loop

    def preview_line(
        self, start: FloatArray, end: FloatArray, rotation: FloatArray, seconds: float
    ) -> list[FloatArray] | None:
        """The postures :meth:`line` (without ``q_end``) would command from the arm's posture
        now, one per control step, solved offline; ``None`` where IK loses the line."""
        progress = steps(seconds)
        return self._preview([(start + (end - start) * s, rotation) for s in progress])

    def steady_line(
        self,
        start: FloatArray,
        end: FloatArray,
        rotation: FloatArray,
        seconds: float,
        max_speed: float,
        margin: float = MIN_MARGIN,
    ) -> list[FloatArray] | None:
        """:meth:`preview_line`'s postures where IK follows the whole line with no joint
        faster than ``max_speed`` (rad/s) and none within ``margin`` (rad) of its limit,
        else ``None``: near a singularity a straight line whips a joint round, and a servo at
        its limit strays off the line (either flings what the hand holds)."""
        postures = self.preview_line(start, end, rotation, seconds)
        if postures is None:
            return None
        q = np.array([arm_qpos(self.loop.model, self.loop.data), *postures])
        if float(np.max(np.abs(np.diff(q, axis=0)))) / CONTROL_DT > max_speed:
            return None
        if self.core.near_limit(postures, margin):
            return None
        return postures

    def glide(
        self,
        end: FloatArray,
        rotation: FloatArray | None,
        seconds: float,
        gripper: float,
        q_end: FloatArray,
        about: FloatArray | None = None,
    ) -> bool:
        """Carry the hand (pointing down) in a straight line from where it is to ``end``,
        turning it about the vertical to ``rotation`` on the way (``None``: keeping its
        heading, to the swing on an arc) and pulling the posture
        towards ``q_end``: a joint-space move between two top-down postures tilts the hand
        midway, which swings an object held off its centre of mass out of the fingers.
        With ``about`` (a point, world), the hand swings round the vertical through it
        instead (:func:`arc_poses`). Previewed first with the held object carried and
        checked as densely as a joint-space move (:func:`spaced_postures`: a held object
        passes through a thin rim between two checks farther apart); ``False``, nothing
        moved, where IK loses the path, a joint would reach its limit or something would be
        touched."""
        start, now_rot = self.core.tcp()
        if now_rot[2, 2] > -0.99 or (rotation is not None and rotation[2, 2] > -0.99):
            return False  # not pointing down
        h0 = math.atan2(now_rot[1, 0], now_rot[0, 0])
        h1 = None if rotation is None else math.atan2(rotation[1, 0], rotation[0, 0])
        turn = glide_turn(start, end, about, h0, h1)
        progress = steps(seconds)
        if about is None:
            poses = [
                (start + (end - start) * s, top_down_rotation(h0 + turn * s)) for s in progress
            ]
        else:
            poses = arc_poses(start, end, about, h0, turn, progress)
        q0 = arm_qpos(self.loop.model, self.loop.data)
        rests = [q0 + (q_end - q0) * s for s in progress]
        path = self._preview(poses, rests)
        if path is None or self.core.near_limit(path, GLIDE_MARGIN):
            return False  # at a limit, the servo strays off the line
        query = CollisionQuery.of(set(), gripper, BaseMove.still(), self.core.carried())
        checked = spaced_postures(path, [point for point, _ in poses])
        if any(self.core.collisions(p, query) for p in checked):
            return False
        return self.follow(poses, gripper, rests)

    def _preview(
        self,
        poses: Sequence[tuple[FloatArray, FloatArray]],
        postures: Sequence[FloatArray] | None = None,
        q0: FloatArray | None = None,
        base: BaseMove | None = None,
    ) -> list[FloatArray] | None:
        """The postures :meth:`follow` would command through ``poses`` (pulled towards
        ``postures``), solved offline from the posture now (or ``q0``, with the UAV moved by
        ``base``); ``None`` where IK loses them."""
        data = self.loop.data
        q = arm_qpos(self.loop.model, data) if q0 is None else q0
        out = []
        for i, (point, rotation) in enumerate(poses):
            rest = postures[i] if postures is not None else None
            q, res = self.core.ik.solve(
                data, point, rotation, q, iterations=60, base=base, posture=rest
            )
            if res > 3 * IK_OK:
                return None
            out.append(q)
        return out

    def line_path(
        self,
        q0: FloatArray,
        start: FloatArray,
        end: FloatArray,
        rotation: FloatArray,
        q_end: FloatArray,
        base: BaseMove,
        seconds: float,
    ) -> list[FloatArray] | None:
        """The postures :meth:`line` (with ``q_end``) commands from posture ``q0``, the UAV
        moved by ``base``; ``None`` where IK loses the line."""
        progress = steps(seconds)
        poses = [(start + (end - start) * s, rotation) for s in progress]
        return self._preview(poses, [q0 + (q_end - q0) * s for s in progress], q0, base)

    def line(
        self,
        start: FloatArray,
        end: FloatArray,
        rotation: FloatArray,
        seconds: float,
        gripper: float,
        q_end: FloatArray | None = None,
    ) -> bool:
        """Move the TCP along the straight line ``start`` → ``end`` (minimum-jerk timing)
        keeping ``rotation``; ``False`` where IK loses the line. With ``q_end`` (the planned
        joint angles at ``end``), IK's posture follows the joint-space blend towards them, so
        the arm stays on the branch the plan checked for collisions."""
        q0 = arm_qpos(self.loop.model, self.loop.data)
        progress = steps(seconds)
        poses = ((start + (end - start) * s, rotation) for s in progress)
        if q_end is None:
            return self.follow(poses, gripper)
        return self.follow(poses, gripper, (q0 + (q_end - q0) * s for s in progress))

    def follow(
        self,
        poses: Iterable[tuple[FloatArray, FloatArray]],
        gripper: float,
        postures: Iterable[FloatArray] | None = None,
    ) -> bool:
        """Servo the TCP through ``poses`` (position, orientation), one per control step,
        each solved from the last (and pulled towards ``postures``, one per pose, if given);
        ``False`` (stopping there) where IK loses the path."""
        loop = self.loop
        q = arm_qpos(loop.model, loop.data)
        rests = iter(postures) if postures is not None else None
        for point, rotation in poses:
            rest = next(rests) if rests is not None else None
            q, res = self.core.ik.solve(loop.data, point, rotation, q, iterations=60, posture=rest)
            if res > 3 * IK_OK:
                return False
            set_arm_targets(loop.model, loop.data, q, gripper)
            loop.control_step()
        return True
