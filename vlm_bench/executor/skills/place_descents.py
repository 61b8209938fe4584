"""The ways down to a place's release: top-down descents with the object held, over the
headings a box-like object allows, with the UAV's assists (hovers in front of an open drawer),
preferring those that keep clear of what lies there already."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vlm_bench.executor.motion.arm_core import MIN_MARGIN
from vlm_bench.executor.motion.arm_planner import Reach
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.ik import top_down_rotation
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.release_points import can_drop_into
from vlm_bench.sim.constants import ARM_BASE_BODY, GRIPPER_CLOSED
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode

PLACE_CLEARANCE = 0.01  # m: a way down to a release keeping this clear of the rest is preferred
GLIDE_TOL = 0.2  # rad: a descent planned after a glide must start this close to its end
DRAWER_OUT = (0.36, 0.46)  # m, horizontal: arm base in front of a drawer release point
DRAWER_DEPTHS = (1.0, 0.9)  # m: arm base above it (from a reach scan over an open drawer)
DRAWER_TURNS = (math.pi, math.pi / 2, -math.pi / 2)  # rad: UAV heading turns tried last there


@dataclass(frozen=True, eq=False)
class Drop:
    """Where one place lets go: the held object, the destination, the release point (TCP),
    the point above it the descent starts from, the hand's heading now and what the hand
    may touch (the held object)."""

    held: str
    dest: str
    release: FloatArray
    above: FloatArray
    heading: float
    ignore: set[int]


class Descents:
    """Plans the ways down to a release for one hand."""

    def __init__(self, hand: Hand) -> None:
        self.hand = hand
        self.loop = hand.loop

    def plan_release(self, episode: Episode, drop: Drop) -> tuple[Reach, Drop] | None:
        """The way down to the release, or, where it is not clear (the hand, 0.2 m long,
        meets a wall or what lies there already) and the object may drop in, to just above
        the rim, whichever touches less (the rim's search looks only for ways that do)."""
        rim = drop.release.copy()
        rim[2] = drop.above[2] - 0.03
        at_rim = Drop(drop.held, drop.dest, rim, drop.above, drop.heading, drop.ignore)
        # A clear way to the release, else a clear one to the rim, is what the full searches
        # below would return; those count every contact, and a release deep in a basket
        # often has no clear way, so the clear ways are looked for first.
        if (clear := self._top_down_to(episode, drop, drop.release, 0)) is not None:
            return clear, drop
        drops_in = can_drop_into(self.hand, episode, drop.held, drop.dest)
        if drops_in and (clear := self._top_down_to(episode, drop, rim, 0)) is not None:
            return clear, at_rim
        sol = self._top_down_to(episode, drop, drop.release)
        if drops_in:
            fewer = math.inf if sol is None else sol.hits - 1
            high = self._top_down_to(episode, drop, rim, fewer)
            if high is not None:
                return high, at_rim
        return None if sol is None else (sol, drop)

    def _top_down_to(
        self, episode: Episode, drop: Drop, point: FloatArray, max_hits: float = math.inf
    ) -> Reach | None:
        """The way down from above ``drop``'s release to ``point`` (:meth:`plan_top_down`
        from the arm's posture now, with the drawer's assists), of at most ``max_hits``
        contacts."""
        return self.plan_top_down(
            point,
            drop.above - point,
            drop.heading,
            drop.ignore,
            arm_qpos(self.loop.model, self.loop.data),
            self.drawer_assists(episode, drop.dest, point),
            max_hits=max_hits,
        )

    def descent(self, drop: Drop, base: BaseMove, level: bool = False) -> Reach | None:
        """The clear way down from above the release with the UAV moved by ``base``, starting
        within :data:`GLIDE_TOL` of the arm's posture now (the hand already above), if any;
        ``level``: at the hand's heading now where that way is clear (:meth:`level_descent`)."""
        now = arm_qpos(self.loop.model, self.loop.data)
        if level and (down := self.level_descent(drop, base, now)) is not None:
            return down
        down = self.plan_top_down(
            drop.release,
            drop.above - drop.release,
            drop.heading,
            drop.ignore,
            now,
            [base],
            max_hits=0,
        )
        if down is None or np.max(np.abs(down.q_start - now)) >= GLIDE_TOL:
            return None
        return down

    def level_descent(self, drop: Drop, base: BaseMove, now: FloatArray) -> Reach | None:
        """The way down at the hand's heading now, starting within :data:`GLIDE_TOL` of the
        arm's posture ``now``, touching nothing and ending clear of the joint limits; the
        start may lie nearer a limit than a plan's :data:`MIN_MARGIN` (the arm stands there
        already: the glide brought it, within its own margin)."""
        core = self.hand.core
        rot = self.hand.tcp()[1]
        heading = math.atan2(rot[1, 0], rot[0, 0])
        down = self.plan_top_down(
            drop.release, drop.above - drop.release, heading, drop.ignore, now, [base], 1
        )
        if down is None or np.max(np.abs(down.q_start - now)) >= GLIDE_TOL:
            return None
        if core.ik.limit_margin(down.q_end) < MIN_MARGIN:
            return None
        query = CollisionQuery.of(drop.ignore, GRIPPER_CLOSED, base, core.carried())
        if core.hits_at(core.joint_samples(down.q_start, down.q_end, base), query, limit=0):
            return None
        return down._replace(hits=0)

    def plan_top_down(
        self,
        point: FloatArray,
        approach: FloatArray,
        yaw_rad: float,
        ignore: set[int],
        seed: FloatArray,
        assist: list[BaseMove] | None = None,
        turns: int = 4,
        max_hits: float = math.inf,
    ) -> Reach | None:
        """The top-down motion from ``point + approach`` down to ``point`` with the object
        held, over the four headings equivalent for a box-like object (the first ``turns``
        of them: 1, ``yaw_rad`` alone), preferring those that keep :data:`PLACE_CLEARANCE`
        from the rest; of at most ``max_hits`` contacts (:meth:`ArmPlanner.plan`)."""
        rotations = [top_down_rotation(yaw_rad + k * math.pi / 2) for k in range(turns)]
        return self.hand.planner.plan(
            point,
            approach,
            rotations,
            ignore,
            GRIPPER_CLOSED,
            seed,
            assist,
            PLACE_CLEARANCE,
            max_hits=max_hits,
        )

    def drawer_assists(
        self, episode: Episode, dest: str, release: FloatArray
    ) -> list[BaseMove] | None:
        """For a release into an open drawer, UAV moves to hover in front of it, high: the
        drawer's tall front leaves the arm no way in across it, only down from above; then the
        usual assists; last, the hovers with the UAV turned by one of :data:`DRAWER_TURNS`:
        the base joint turns through 5.8 rad, not a full turn, so from one heading the arm may
        have no way in that another gives. ``None`` (the usual assists) for other
        destinations."""
        part = next((p for p in episode.parts if p.id == dest and p.kind == "drawer"), None)
        if part is None:
            return None
        axis = self.hand.outward_axis(part.parent)
        base = self.loop.data.body(ARM_BASE_BODY).xpos
        hover = [
            np.append(release[:2] + axis[:2] * out, release[2] + depth) - base
            for depth in DRAWER_DEPTHS
            for out in DRAWER_OUT
        ]
        turned = [BaseMove(move, turn) for turn in DRAWER_TURNS for move in hover]
        return [*map(BaseMove, hover), *self.hand.planner.assists(release), *turned]
