"""Choosing a reach: a straight TCP motion onto a point, clear of the scene, among the arm's IK
branches and small UAV moves (assists).

A hanging arm reaches most points on several branches (elbow out over a table, or folded up),
and the first IK solution to converge is not always clear, so every candidate from several
starting postures is checked along the joint-space moves it makes and the plans are ranked:
contacts on the way first, then near misses, then the widest joint swing, then the margin from
the joint limits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from vlm_bench.executor.motion.arm_core import IK_OK, MIN_MARGIN, ArmCore
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import Carried, CollisionQuery
from vlm_bench.executor.motion.flight_clearance import CLIMBS
from vlm_bench.executor.motion.ik import CANDIDATE_STALL, SEED_POSTURES
from vlm_bench.executor.motion.lines import ArmLines
from vlm_bench.sim.constants import ARM_BASE_BODY
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray

DESCENTS = tuple(np.array([0.0, 0.0, dz]) for dz in (0.0, -0.06, -0.12))
"""UAV offsets (m) tried first when the arm alone cannot reach: none, then descents."""
BASE_ASSIST = tuple(BaseMove(d) for d in DESCENTS)
""":data:`DESCENTS` as UAV moves."""
MAX_ASSIST = 0.35  # m, horizontal: a skill adjusts the UAV, it does not fly to the object
SWING_BIN = 0.5  # rad: plans whose widest joint swing differs by less are equally good
HELD_SWING = 2.0  # rad: a wider joint swing with an object in the hand counts as a contact:
# the swing's acceleration can pull the object out of the fingers
SWEEP_STEP = 0.05  # m of the UAV's flight between the collision checks of a held arm's sweep
TURN_STEP = 0.1  # rad of the UAV's heading between the collision checks of its turn
WORK_RADII = (0.36, 0.46, 0.56)
"""Horizontal distances (m) from the arm base where top-down reaches keep far from the joint
limits, for the points the stand-off leaves 0.45-0.75 m below the base (from a reach scan)."""
NO_PLAN = (math.inf, math.inf, math.inf, -math.inf)
"""The rank of no plan: any plan ranks lower (better)."""


class Reach(NamedTuple):
    """A planned straight TCP motion: joint angles at its start, the hand's orientation, the
    UAV move to make first, joint angles at its end, and how many contacts the arm would make
    on the way (0: a clear path)."""

    q_start: FloatArray
    rotation: FloatArray
    shift: BaseMove
    q_end: FloatArray
    hits: int


@dataclass(frozen=True, eq=False)
class _Target:
    """What :meth:`ArmPlanner.plan` is asked for (see its arguments)."""

    point: FloatArray
    approach: FloatArray
    ignore: set[int]
    gripper: float
    clearance: float
    line: float | None
    turn_room: float
    carried: Carried | None
    """The held object, as the hand carries it now."""


class ArmPlanner:
    """Plans reaches for one loop's arm.

    Args:
        core: The arm (IK, collision queries).
        lines: Its straight motions (a reach made as a line is checked along the line).
    """

    def __init__(self, core: ArmCore, lines: ArmLines) -> None:
        self.core = core
        self.lines = lines
        self.loop = core.loop

    def plan(
        self,
        point: FloatArray,
        approach: FloatArray,
        rotations: Sequence[FloatArray],
        ignore: set[int],
        gripper: float,
        seed: FloatArray,
        assist: Sequence[BaseMove] | None = None,
        clearance: float = 0.0,
        line: float | None = None,
        turn_room: float = 0.0,
        max_hits: float = math.inf,
    ) -> Reach | None:
        """The straight TCP motion from ``point + approach`` to ``point``: joint angles at
        both ends, the hand's orientation and the UAV move to make first.

        IK starts from ``seed``, the arm's posture now and the known postures. Every
        candidate is checked along its joint-space moves (now to the start, start to end) with
        the held object carried, and the plans ranked (:meth:`_candidate`). The way to the
        start must keep off ``ignore`` (the object to grasp or push, a handle): only the final
        motion may touch it. Where no plan is clear from the UAV's pose, the UAV may move by
        one of ``assist`` (tried in order; default :meth:`assists`; a turn's contacts count,
        :meth:`turn_hits`); the best plan over all is returned. With ``clearance`` (m), of the
        clear plans for one UAV move those whose motion from start to end keeps that far from
        everything outside ``ignore`` come first: the arm sways as it stretches, so a path
        planned to pass an edge by less is not safe. The motion from start to end is checked
        as a joint-space move or, for a caller that makes it as a line of ``line`` seconds,
        along the postures that line commands (:meth:`ArmLines.line_path`; its last is the
        plan's end): a line can take the arm far off the joint-space blend. With
        ``turn_room`` (rad), a base joint nearer its limit than that at either end counts as
        a contact: the arm cannot turn further that way for what follows. Plans with more
        than ``max_hits`` contacts are not wanted (``0``: a clear plan or ``None``); their
        checks stop at the first contact over it.
        """
        now = arm_qpos(self.loop.model, self.loop.data)
        carried = self.core.carried()
        target = _Target(point, approach, ignore, gripper, clearance, line, turn_room, carried)
        starts = _distinct([np.asarray(seed), now, *map(np.asarray, SEED_POSTURES)])
        shifts = self.assists(point) if assist is None else assist
        search = (target, rotations, starts, shifts, now)
        if max_hits > 0 and (clear := self._search(*search, 0.0)) is not None:
            return clear
        return self._search(*search, max_hits)

    def _search(
        self,
        target: _Target,
        rotations: Sequence[FloatArray],
        starts: list[FloatArray],
        shifts: Sequence[BaseMove],
        now: FloatArray,
        max_hits: float,
    ) -> Reach | None:
        """:meth:`plan`'s search for the best plan of at most ``max_hits`` contacts.

        :meth:`plan` searches twice: first for a clear plan (``max_hits=0``: every check
        stops at its first contact), then, where there is none, for the best of the rest.
        The first search finds the plan the second would (a clear candidate is checked the
        same way whatever the best so far, and ranks before any other), and the second's
        IK solves and collision checks are mostly the first's, answered from their caches."""
        carried = target.carried
        held = carried.geoms if carried is not None else set()
        best: Reach | None = None
        best_key = (float(max_hits), *NO_PLAN[1:])
        for shift in shifts:
            turning = self.turn_hits(shift, now, held, carried)
            if turning > best_key[0]:
                continue  # every plan with this move makes more contacts than the best
            for rot in rotations:
                for start in starts:
                    found = self._candidate(target, rot, start, shift, now, turning, best_key)
                    if found is None:
                        continue
                    reach, key = found
                    if key < best_key:
                        best, best_key = reach, key
                    if key[0] == 0 and key[1] == 0:
                        break  # other starts would find this branch or one as good
            if best is not None and best_key[0] == 0:
                return best
        return best

    def _candidate(
        self,
        target: _Target,
        rot: FloatArray,
        start: FloatArray,
        shift: BaseMove,
        now: FloatArray,
        turning: int,
        best_key: tuple[float, float, float, float],
    ) -> tuple[Reach, tuple[float, float, float, float]] | None:
        """The plan IK finds from ``start`` and its rank (contacts, near miss, swing bin,
        negated limit margin), or ``None`` where IK fails or it cannot beat ``best_key``.

        A posture under :data:`MIN_MARGIN` from a joint limit counts as a contact (a servo at
        its limit strays off the plan), and so does, with an object in the hand, a swing to
        the start wider than :data:`HELD_SWING`."""
        ik, data = self.core.ik, self.loop.data
        q_end, res = ik.solve(data, target.point, rot, start, base=shift, stall=CANDIDATE_STALL)
        if res > IK_OK:
            return None
        carried = target.carried
        down = CollisionQuery.of(target.ignore, target.gripper, shift, carried)
        room = best_key[0] - turning
        if (
            target.line is None
            and room < math.inf
            and self.core.hits_at([q_end], down, room) > room
        ):
            return None  # the end alone makes more contacts than the best plan: the way down
            # (a joint-space move, its end included) makes at least as many
        q_start, res = ik.solve(
            data, target.point + target.approach, rot, q_end, base=shift, stall=CANDIDATE_STALL
        )
        if res > IK_OK:
            return None
        held = carried.geoms if carried is not None else set()
        way_in = CollisionQuery.of(held, target.gripper, shift, carried)
        margin = ik.limit_margin(q_start)
        widest = float(np.max(np.abs(q_start - now)))
        hits = turning + int(margin < MIN_MARGIN) + int(carried is not None and widest > HELD_SWING)
        swing = round(widest / SWING_BIN)
        if hits and (hits, 0.0, swing, -margin) >= best_key:
            return None  # the ways in and down only add contacts: it cannot do better
        # Contacts are counted last and only as far as they can still beat the best plan.
        hits += self.core.path_hits(now, q_start, way_in, limit=best_key[0] - hits, end_first=True)
        if hits and (hits, 0.0, swing, -margin) >= best_key:
            return None  # the way down only adds contacts: it cannot do better
        final = self._final_way(target, rot, q_start, q_end, shift)
        if final is None:
            return None  # IK loses the line
        way, q_end = final
        if margin >= MIN_MARGIN > ik.limit_margin(q_end):
            hits += 1
        margin = min(margin, ik.limit_margin(q_end))
        hits += int(min(ik.room(q_start)[0], ik.room(q_end)[0]) < target.turn_room)
        if hits > best_key[0]:
            return None  # the joint limits alone make more contacts than the best plan
        hits += self.core.hits_at(way, down, limit=best_key[0] - hits)
        if hits > best_key[0]:
            return None  # more contacts than the best plan
        graze = hits == 0 and bool(
            target.clearance and self.core.hits_at(way, down.near(target.clearance), limit=0)
        )
        key = (float(hits), float(graze), float(swing), -margin)
        return Reach(q_start, rot, shift, q_end, hits), key

    def _final_way(
        self,
        target: _Target,
        rot: FloatArray,
        q_start: FloatArray,
        q_end: FloatArray,
        shift: BaseMove,
    ) -> tuple[list[FloatArray], FloatArray] | None:
        """The postures of the motion from start to end, and its last: the joint-space move's,
        or the line's where the caller makes one (``None`` where IK loses it)."""
        if target.line is None:
            return self.core.joint_samples(q_start, q_end, shift), q_end
        path = self.lines.line_path(
            q_start, target.point + target.approach, target.point, rot, q_end, shift, target.line
        )
        if path is None:
            return None
        return path, path[-1]  # each control step's posture

    def back_off(self, point: FloatArray, within: float, to: float) -> FloatArray | None:
        """The horizontal UAV offset (m, world) that puts ``point`` ``to`` m (horizontally)
        from the arm base, when it now lies closer than ``within`` (and not right below it):
        away from the point, or towards it where it lies farther than ``to``."""
        base = self.loop.data.body(ARM_BASE_BODY).xpos
        away = base[:2] - np.asarray(point)[:2]
        dist = float(np.linalg.norm(away))
        if not 1e-6 < dist < within:
            return None
        return np.append(away / dist * (to - dist), 0.0)

    def assists(self, point: FloatArray) -> list[BaseMove]:
        """UAV moves that may bring ``point`` into the arm's top-down workspace, smallest
        first: none and small descents; horizontal moves putting the point at one of
        :data:`WORK_RADII` from the arm base, or as near as :data:`MAX_ASSIST` allows, with
        and without a descent; last, climbs, so the arm reaches down into a deep opening (an
        open drawer under its tall front) from above rather than across its rim. Close under
        the base a top-down reach folds the elbow onto its limit; far out the arm stretches."""
        radial: list[FloatArray] = []
        for radius in WORK_RADII:
            move = self.back_off(point, math.inf, radius)
            if move is None or np.linalg.norm(move) <= 0.04:
                continue
            move *= min(1.0, MAX_ASSIST / float(np.linalg.norm(move)))  # no farther than that
            if not any(np.allclose(move, m, atol=0.01) for m in radial):
                radial.append(move)
        radial.sort(key=lambda m: float(np.linalg.norm(m)))
        level = [move + dz for move in radial for dz in DESCENTS[:2]]
        climbs = [move + lift for lift in CLIMBS for move in radial]
        return [BaseMove(m) for m in (*DESCENTS, *level, *CLIMBS, *climbs)]

    def turn_hits(
        self, move: BaseMove, q: FloatArray, ignore: set[int], carried: Carried | None
    ) -> int:
        """Contacts outside ``ignore`` while the UAV makes ``move``'s turn with the arm held
        at ``q`` and ``carried`` in the hand, at the move's higher end, where
        :func:`~vlm_bench.executor.motion.uav_moves.shift_base` makes it, every
        :data:`TURN_STEP` rad: an arm reaching out sweeps a wide circle as the UAV turns."""
        hits = self._sweep_hits(move, q, ignore, carried)
        if not move.yaw:
            return hits
        at = np.zeros(3) if move.turns_first else np.asarray(move.xyz)
        n = math.ceil(abs(float(move.yaw)) / TURN_STEP)
        return hits + sum(
            len(
                self.core.collisions(
                    q, CollisionQuery.of(ignore, None, BaseMove(at, move.yaw * k / n), carried)
                )
            )
            for k in range(1, n + 1)
        )

    def _sweep_hits(
        self, move: BaseMove, q: FloatArray, ignore: set[int], carried: Carried | None
    ) -> int:
        """Contacts outside ``ignore`` while the UAV flies ``move``'s horizontal part with an
        object in the hand and the arm held at ``q``, every :data:`SWEEP_STEP` m: an arm
        holding an object low drags what it passes along (the empty arm is stowed first)."""
        xyz = np.asarray(move.xyz)
        length = float(np.linalg.norm(xyz[:2]))
        if carried is None or length < 1e-6:
            return 0
        yaw = move.yaw if move.turns_first else 0.0
        n = math.ceil(length / SWEEP_STEP)
        return sum(
            len(
                self.core.collisions(
                    q, CollisionQuery.of(ignore, None, BaseMove(xyz * k / n, yaw), carried)
                )
            )
            for k in range(1, n + 1)
        )


def _distinct(postures: list[FloatArray]) -> list[FloatArray]:
    """``postures`` without repeats (the seed is often the posture now or a known one): a
    repeated start gives the same candidate again."""
    seen: set[bytes] = set()
    out = []
    for q in postures:
        key = np.asarray(q, np.float64).tobytes()
        if key not in seen:
            seen.add(key)
            out.append(q)
    return out
