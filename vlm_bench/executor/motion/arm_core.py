"""One loop's arm for planning: IK, collision queries along joint-space paths, the held object.

Every motion module (lines, flight clearance, the stow, the planner) works through an
:class:`ArmCore`, so one IK solver and one collision checker (with their caches) serve them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import Carried, CollisionChecker, CollisionQuery
from vlm_bench.executor.motion.ik import SEED_POSTURES, ArmIk
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import TCP_SITE
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.objects.builder_kit import free_joint_name
from vlm_bench.types.base import FloatArray

IK_OK = 0.02  # residual (m + rad) accepted
MIN_MARGIN = 0.05  # rad from the joint limits for a plan to count as clear
PATH_STEP = 0.1  # rad of the widest joint swing between the checks of a joint-space move...
PATH_TRAVEL = 0.01  # ...or m of the TCP's travel, where that is closer: no finger may pass
# through a thin wall (a basket's rim) between two checks


class ArmCore:
    """The arm of one simulation loop, with its IK solver and collision checker.

    Args:
        loop: The loop the skills run on.
    """

    def __init__(self, loop: SimLoop) -> None:
        self.loop = loop
        self.ik = ArmIk(loop.model)
        self.checker = CollisionChecker(loop.model)

    def solve_any(
        self,
        point: FloatArray,
        rotation: FloatArray,
        seed: FloatArray,
        base: BaseMove | None = None,
    ) -> tuple[FloatArray, float]:
        """IK from ``seed``, then from the known postures, until one converges."""
        best: tuple[FloatArray, float] = (seed, math.inf)
        for start in (seed, *SEED_POSTURES):
            q, res = self.ik.solve(self.loop.data, point, rotation, np.asarray(start), base=base)
            if res < best[1]:
                best = (q, res)
            if res < IK_OK:
                break
        return best

    def collisions(self, q: FloatArray, query: CollisionQuery) -> list[int]:
        """What the robot would touch with arm angles ``q`` (see
        :meth:`CollisionChecker.collisions`)."""
        return self.checker.collisions(self.loop.data, q, query)

    def path_hits(
        self,
        q_from: FloatArray,
        q_to: FloatArray,
        query: CollisionQuery,
        limit: float = math.inf,
        end_first: bool = False,
    ) -> int:
        """Contacts along the joint-space move ``q_from`` → ``q_to`` (sampled every
        :data:`PATH_STEP` rad of the widest joint swing or :data:`PATH_TRAVEL` m of the TCP's
        travel, whichever is closer, the end included) for ``query``, counted as
        :meth:`hits_at` counts them. ``end_first``: the same samples checked from the end
        back, for a move whose end lies near the scene (a reach down to an object): a path
        over ``limit`` is then found over it after fewer checks, and one within it sums the
        same contacts either way."""
        samples = self.joint_samples(q_from, q_to, query.base, query.clearance)
        return self.hits_at(reversed(samples) if end_first else samples, query, limit)

    def joint_samples(
        self,
        q_from: FloatArray,
        q_to: FloatArray,
        base: BaseMove | None,
        clearance: float = 0.0,
    ) -> list[FloatArray]:
        """Postures along the joint-space move ``q_from`` → ``q_to`` (UAV moved by ``base``)
        for :meth:`path_hits`, evenly spaced, the end included; a check for ``clearance``
        (m) needs them no closer than that."""
        n = max(4, math.ceil(float(np.max(np.abs(q_to - q_from))) / PATH_STEP))
        tcp = [
            self.ik.tcp_at(self.loop.data, q_from + (q_to - q_from) * k / n, base)
            for k in range(n + 1)
        ]
        longest = float(np.max(np.linalg.norm(np.diff(tcp, axis=0), axis=1)))
        n = max(n, math.ceil(n * longest / max(PATH_TRAVEL, clearance)))
        # The same floats as [q_from + (q_to - q_from) * k / n for k in 1..n], as one array.
        steps = np.arange(1, n + 1, dtype=np.float64)[:, None]
        return list(q_from + (q_to - q_from) * steps / n)

    def hits_at(
        self, postures: Iterable[FloatArray], query: CollisionQuery, limit: float = math.inf
    ) -> int:
        """Contacts for ``query`` at each of ``postures``, summed; the count stops at the
        first posture that takes it over ``limit`` (``limit=0``: whether there is any), so a
        caller that only needs to know it is over pays for no more checks."""
        data, total = self.loop.data, 0
        for q in postures:
            total += len(self.checker.collisions(data, q, query))
            if total > limit:
                break
        return total

    def near_limit(self, postures: Sequence[FloatArray], margin: float) -> bool:
        """Whether a joint comes within ``margin`` (rad) of its limit in one of ``postures``."""
        return min(self.ik.limit_margin(p) for p in postures) < margin

    def carried(self) -> Carried | None:
        """The held object as the hand carries it (pose relative to the TCP now), if any."""
        held = self.loop.held
        if held is None:
            return None
        data = self.loop.data
        tcp, rot = self.tcp()
        body = data.body(held)
        return Carried(
            qadr=int(self.loop.model.joint(free_joint_name(held)).qposadr[0]),
            geoms=self.body_geoms(held),
            offset=rot.T @ (np.array(body.xpos) - tcp),
            rotation=rot.T @ np.array(body.xmat).reshape(3, 3),
        )

    def tcp(self) -> tuple[FloatArray, FloatArray]:
        """The TCP's position and orientation now (world)."""
        site = self.loop.data.site(TCP_SITE)
        return np.array(site.xpos), np.array(site.xmat).reshape(3, 3)

    def body_geoms(self, body: str) -> set[int]:
        """Geoms of ``body`` and its children."""
        return set(subtree_geoms(self.loop.model, self.loop.model.body(body).id))


def spaced_postures(
    postures: Sequence[FloatArray], points: Sequence[FloatArray]
) -> list[FloatArray]:
    """Of the postures a servoed path commands (the TCP at ``points``), those a check of the
    path visits: consecutive ones at most :data:`PATH_TRAVEL` m of the TCP's travel and
    :data:`PATH_STEP` rad of the widest joint swing apart, as :meth:`ArmCore.joint_samples`
    spaces a joint-space move (where one control step goes farther, both its ends), the end
    included."""
    kept = [0]
    for i in range(1, len(postures)):
        last, nxt = kept[-1], min(i + 1, len(postures) - 1)
        travel = float(np.linalg.norm(points[nxt] - points[last])) / PATH_TRAVEL
        swing = float(np.max(np.abs(postures[nxt] - postures[last]))) / PATH_STEP
        if i == len(postures) - 1 or max(travel, swing) > 1.0:
            kept.append(i)
    return [postures[i] for i in kept]
