"""Arm motions the scripted skills share: IK planning with collision checks, straight-line TCP
moves, finger-contact tests and small UAV base adjustments, all on one simulation loop."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from vlm_bench.executor.ik import SEED_POSTURES, ArmIk, Carried, top_down_rotation
from vlm_bench.executor.loop import SimLoop
from vlm_bench.executor.motion import HELD_JOINT_SPEED, joint_move, min_jerk
from vlm_bench.executor.uav_move import STOWED_TOL, fly_to, stow_arm, turn_to
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects.base import free_joint_name
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.robot import arm_qpos, gripper_target, set_arm_targets

Vec = NDArray[np.float64]
IK_OK = 0.02  # residual (m + rad) accepted
BASE_ASSIST = tuple(np.array([0.0, 0.0, dz]) for dz in (0.0, -0.06, -0.12))
"""UAV moves (m) tried, in order, when the arm alone cannot reach: descents."""
MAX_ASSIST = 0.35  # m, horizontal: a skill adjusts the UAV, it does not fly to the object
MIN_MARGIN = 0.05  # rad from the joint limits for a plan to count as clear
SWING_BIN = 0.5  # rad: plans whose widest joint swing differs by less are equally good
HELD_SWING = 2.0  # rad: a wider joint swing with an object in the hand counts as a contact
# (a bottle hung by its cap slipped out of the fingers in a 4.9 rad turn of the base joint)
GLIDE_MARGIN = 0.01  # rad: the nearest a glide may bring a joint to its limit (0: IK's clamp)
STOW_CLEARANCE = 0.05  # m the stow's planned way keeps from everything, or the UAV climbs
PATH_STEP = 0.1  # rad of the widest joint swing between the checks of a joint-space move...
PATH_TRAVEL = 0.01  # ...or m of the TCP's travel, where that is closer (a finger swept through
# a basket's rim between two checks 0.1 rad apart)
CLIMBS = tuple(np.array([0.0, 0.0, dz]) for dz in (0.15, 0.3))
"""UAV climbs (m) tried after every level move."""
FLIGHT_CLEARANCE = 0.03  # m a flight with an object in the hand keeps from everything, if it can
FLIGHT_STEP = 0.05  # m between the collision checks of a flight with an object in the hand
TURN_STEP = 0.1  # rad of the UAV's heading between the collision checks of its turn
CARRY_TURNS = tuple(sign * turn for turn in (0.4, 0.8, 1.2, 1.6) for sign in (1.0, -1.0))
"""Turns of the arm's base joint (rad) tried to carry a held object clear of a flight's way."""
WORK_RADII = (0.36, 0.46, 0.56)
"""Horizontal distances (m) from the arm base where top-down reaches keep far from the joint
limits, for the points the stand-off leaves 0.45-0.75 m below the base (from a reach scan)."""


class Reach(NamedTuple):
    """A planned straight TCP motion: joint angles at its start, the hand's orientation, the
    UAV move (m; a fourth value, where given, turns its heading, rad) to make first, joint
    angles at its end, and how many contacts the arm would make on the way (0: a clear
    path)."""

    q_start: Vec
    rotation: Vec
    shift: Vec
    q_end: Vec
    hits: int


class Arm:
    """The arm of one simulation loop, with its IK solver.

    Args:
        loop: The loop the skills run on.
    """

    def __init__(self, loop: SimLoop) -> None:
        self.loop = loop
        self.ik = ArmIk(loop.model)
        self._fingers = {
            side: set(subtree_geoms(loop.model, loop.model.body(name).id))
            for side, name in (("l", c.LEFT_FINGER_BODY), ("r", c.RIGHT_FINGER_BODY))
        }

    def solve_any(
        self, point: Vec, rotation: Vec, seed: Vec, base: Vec | None = None
    ) -> tuple[Vec, float]:
        """IK from ``seed``, then from the known postures, until one converges."""
        best: tuple[Vec, float] = (seed, math.inf)
        for start in (seed, *SEED_POSTURES):
            q, res = self.ik.solve(self.loop.data, point, rotation, np.asarray(start), base=base)
            if res < best[1]:
                best = (q, res)
            if res < IK_OK:
                break
        return best

    def plan(
        self,
        point: Vec,
        approach: Vec,
        rotations: Sequence[Vec],
        ignore: set[int],
        gripper: float,
        seed: Vec,
        assist: Sequence[Vec] | None = None,
        clearance: float = 0.0,
        line: float | None = None,
        turn_room: float = 0.0,
    ) -> Reach | None:
        """The straight TCP motion from ``point + approach`` to ``point``: joint angles at
        both ends, the hand's orientation and the UAV move to make first.

        IK starts from ``seed``, the arm's posture now and the known postures: a hanging arm
        reaches most points on several branches (elbow out over a table, or folded up), and the
        first to converge is not always clear of the table. Every candidate is checked along
        its joint-space moves (now to the start, start to end) with the held object carried,
        and the plans compared by contacts on the way, then by the widest joint swing from
        now (a wide swing can fling a held object), then by the margin from the joint limits
        (under :data:`MIN_MARGIN` counts as a contact: a servo at its limit strays off the plan;
        so does a swing over :data:`HELD_SWING` with an object in the hand, and, with
        ``turn_room`` (rad), a base joint nearer its limit than that at either end: the arm
        cannot turn further that way, and a can grasped 0.09 rad off it had no way left to
        the bowl beside it but a swing that flung it).
        Where no plan is clear from the UAV's pose, the UAV may move by one of ``assist``
        (tried in order; default :meth:`assists`; one that also turns its heading counts the
        contacts of the turn, :meth:`turn_hits`); the best plan over all is returned.
        With ``clearance`` (m), of the clear plans for one UAV move those whose motion from
        start to end keeps that far from everything (outside ``ignore``) come first: a hand
        planned to pass a box's rim 1 mm off hit it, the arm swaying as it stretched down.
        The motion from start to end is checked as a joint-space move, or, for a caller that
        makes it as a :meth:`line` of ``line`` seconds, along the postures that line commands
        (:meth:`line_path`; its last is the plan's end): from start to end a line can take
        the arm far off the joint-space blend (a teddy bear's grasp put the elbow on the
        table).
        """
        data = self.loop.data
        if assist is None:
            assist = self.assists(point)
        now = arm_qpos(self.loop.model, data)
        carried = self.carried()
        # ``ignore`` (the object to grasp or push, a handle) may be touched on the final line
        # only: the way to its start must keep off it, or it knocks a tall bottle over.
        held = carried.geoms if carried is not None else set()
        starts = [np.asarray(seed), now, *map(np.asarray, SEED_POSTURES)]
        best: Reach | None = None
        best_key = (math.inf, math.inf, math.inf, -math.inf)
        for shift in assist:
            turning = self.turn_hits(shift, now, held, carried)
            for rot in rotations:
                for start in starts:
                    q_end, res = self.ik.solve(data, point, rot, start, base=shift)
                    if res > IK_OK:
                        continue
                    q_start, res = self.ik.solve(data, point + approach, rot, q_end, base=shift)
                    if res > IK_OK:
                        continue
                    hits = turning + self.path_hits(now, q_start, held, gripper, shift, carried)
                    margin = self.ik.limit_margin(q_start)
                    widest = float(np.max(np.abs(q_start - now)))
                    hits += self._strain(margin, widest, carried is not None)
                    swing = round(widest / SWING_BIN)
                    if hits and (hits, 0.0, swing, -margin) >= best_key:
                        continue  # the way down only adds contacts: it cannot do better
                    if line is None:
                        way = self._joint_samples(q_start, q_end, shift)
                    else:
                        path = self.line_path(
                            q_start, point + approach, point, rot, q_end, shift, line
                        )
                        if path is None:
                            continue  # IK loses the line
                        way, q_end = path, path[-1]  # each control step's posture
                    hits += self.hits_at(way, ignore, gripper, shift, carried)
                    if margin >= MIN_MARGIN > self.ik.limit_margin(q_end):
                        hits += 1
                    margin = min(margin, self.ik.limit_margin(q_end))
                    hits += int(min(self.ik.room(q_start)[0], self.ik.room(q_end)[0]) < turn_room)
                    graze = hits == 0 and bool(
                        clearance and self.hits_at(way, ignore, gripper, shift, carried, clearance)
                    )
                    key = (float(hits), float(graze), float(swing), -margin)
                    if key < best_key:
                        best, best_key = Reach(q_start, rot, shift, q_end, hits), key
                    if hits == 0 and not graze:
                        break  # other starts would find this branch or one as good
            if best is not None and best_key[0] == 0:
                return best
        return best

    @staticmethod
    def _strain(margin: float, widest: float, holding: bool) -> int:
        """Contacts a plan counts for a posture ``margin`` (rad) from a joint limit (under
        :data:`MIN_MARGIN` a servo strays off the plan) and, ``holding`` an object, for a
        swing wider than :data:`HELD_SWING` (rad) to its start."""
        return int(margin < MIN_MARGIN) + int(holding and widest > HELD_SWING)

    def path_hits(
        self,
        q_from: Vec,
        q_to: Vec,
        ignore: set[int],
        gripper: float,
        base: Vec,
        carried: Carried | None = None,
        clearance: float = 0.0,
    ) -> int:
        """Contacts outside ``ignore`` along the joint-space move ``q_from`` → ``q_to``
        (sampled every :data:`PATH_STEP` rad of the widest joint swing or
        :data:`PATH_TRAVEL` m of the TCP's travel, whichever is closer, the end included),
        with the UAV moved by ``base`` and ``carried`` in the hand (or, with ``clearance``,
        m, approaches closer than that)."""
        samples = self._joint_samples(q_from, q_to, base, clearance)
        return self.hits_at(samples, ignore, gripper, base, carried, clearance)

    def _joint_samples(
        self, q_from: Vec, q_to: Vec, base: Vec, clearance: float = 0.0
    ) -> list[Vec]:
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
        return [q_from + (q_to - q_from) * k / n for k in range(1, n + 1)]

    def hits_at(
        self,
        postures: Iterable[Vec],
        ignore: set[int],
        gripper: float,
        base: Vec,
        carried: Carried | None = None,
        clearance: float = 0.0,
    ) -> int:
        """:meth:`path_hits` at each of ``postures``."""
        data = self.loop.data
        return sum(
            len(self.ik.collisions(data, q, ignore, gripper, base, carried, clearance))
            for q in postures
        )

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

    def clear_for_flight(self, travel: Vec) -> float | None:
        """Before the UAV flies ``travel`` (m, world) with an object in the hand: where the
        robot or the object, carried as it hangs now, would come within
        :data:`FLIGHT_CLEARANCE` of something on the way (a drawer's front the flight stops
        at), turn the arm's base joint, smallest turn first, to a posture from which the whole
        flight keeps that clear (else, failing any, merely touches nothing: the flying UAV
        sways, and a forearm planned to pass a basket 1 cm off knocked a nut in the hand onto
        its rim). The turn made (rad, 0 for none; undo it with :meth:`turn_back` after the
        flight), ``None`` where no turn clears the flight."""
        if self.loop.held is None:
            return 0.0
        now = arm_qpos(self.loop.model, self.loop.data)
        for clearance in (FLIGHT_CLEARANCE, 0.0):
            clear = functools.partial(self.flight_clear, travel, clearance=clearance)
            if clear(now):
                return 0.0
            for turn in CARRY_TURNS:
                if self._turn(turn, clear):
                    return turn
        return None

    def flight_climb(self, travel: Vec) -> Vec:
        """Where no turn clears a flight of ``travel`` (m, world) with an object in the hand:
        the least of :data:`CLIMBS` for the UAV to climb first and fly the flight that much
        higher, both clear (an arm the pick left reaching out low ends the flight in a basket
        beside its stop); none (zeros) where neither is clear."""
        for climb in CLIMBS:
            if self.flight_clear(climb) and self.flight_clear(travel, start=climb):
                return climb
        return np.zeros(3)

    def flight_clear(
        self,
        travel: Vec,
        q: Vec | None = None,
        clearance: float = 0.0,
        start: Vec | None = None,
    ) -> bool:
        """Whether the robot, with arm angles ``q`` (default: as now) and the held object
        carried, touches nothing (comes no closer than ``clearance``, m) while the UAV flies
        ``travel`` (m, world), from where it is (or moved by ``start``)."""
        data, carried = self.loop.data, self.carried()
        q = arm_qpos(self.loop.model, data) if q is None else q
        n = max(1, math.ceil(float(np.linalg.norm(travel)) / FLIGHT_STEP))
        first = np.zeros(3) if start is None else np.asarray(start)
        ways = [first + np.asarray(travel) * k / n for k in range(n + 1)]
        return not any(
            self.ik.collisions(data, q, set(), None, b, carried, clearance) for b in ways
        )

    def turn_back(self, turn: float | None) -> None:
        """Undo :meth:`clear_for_flight`'s turn of the base joint after the flight, where the
        way back is clear: the arm turned near its limit leaves a place no clear way to its
        release but a wide swing, which flings a held object."""
        if turn:
            self._turn(-turn, lambda _q: True)

    def _turn(self, turn: float, clear: Callable[[Vec], bool]) -> bool:
        """Turn the base joint by ``turn`` (rad), holding the object, where the posture it
        ends in keeps off the joint limits and is ``clear`` and the way there touches
        nothing; whether it turned."""
        now = arm_qpos(self.loop.model, self.loop.data)
        q = now.copy()
        q[0] += turn
        if self.ik.limit_margin(q) < MIN_MARGIN or not clear(q):
            return False
        carried = self.carried()
        if self.path_hits(now, q, set(), c.GRIPPER_CLOSED, np.zeros(3), carried):
            return False
        joint_move(self.loop, q, 1.0, None, HELD_JOINT_SPEED)
        return True

    def back_off(self, point: Vec, within: float, to: float) -> Vec | None:
        """The horizontal UAV move that puts ``point`` ``to`` m (horizontally) from the arm
        base, when it now lies closer than ``within`` (and not right below it): away from the
        point, or towards it where it lies farther than ``to``."""
        base = self.loop.data.body(c.ARM_BASE_BODY).xpos
        away = base[:2] - np.asarray(point)[:2]
        dist = float(np.linalg.norm(away))
        if not 1e-6 < dist < within:
            return None
        return np.append(away / dist * (to - dist), 0.0)

    def assists(self, point: Vec) -> list[Vec]:
        """UAV moves that may bring ``point`` into the arm's top-down workspace, smallest
        first: none and small descents; horizontal moves putting the point at one of
        :data:`WORK_RADII` from the arm base, or as near as :data:`MAX_ASSIST` allows (a
        basket right under the UAV ends 0.35 m out), with and without a descent; last, climbs, so
        the arm reaches down into a deep opening (an open drawer under its tall front) from
        above rather than across its rim. Close under the base a top-down reach folds the
        elbow onto its limit; far out the arm stretches."""
        radial: list[Vec] = []
        for radius in WORK_RADII:
            move = self.back_off(point, math.inf, radius)
            if move is None or np.linalg.norm(move) <= 0.04:
                continue
            move *= min(1.0, MAX_ASSIST / float(np.linalg.norm(move)))  # no farther than that
            if not any(np.allclose(move, m, atol=0.01) for m in radial):
                radial.append(move)
        radial.sort(key=lambda m: float(np.linalg.norm(m)))
        level = [move + dz for move in radial for dz in BASE_ASSIST[:2]]
        climbs = [move + lift for lift in CLIMBS for move in radial]
        return [*BASE_ASSIST, *level, *CLIMBS, *climbs]

    def shift_base(self, delta: Vec) -> None:
        """Fly the UAV's setpoint by ``delta`` (m, world) and let it settle; a fourth value,
        where given, turns its heading by that much (rad, CCW) at the move's higher end
        (:meth:`turn_hits` checks the turn there)."""
        delta = np.asarray(delta, dtype=np.float64)
        turn = float(delta[3]) if len(delta) > 3 else 0.0
        if turn and _turns_first(delta):
            turn_to(self.loop, turn, self.loop.config.flight)
        if np.any(delta[:3]):
            target = np.array(self.loop.controller.setpoint) + delta[:3]
            fly_to(self.loop, target, self.loop.config.flight)
        if turn and not _turns_first(delta):
            turn_to(self.loop, turn, self.loop.config.flight)

    def turn_hits(self, move: Vec, q: Vec, ignore: set[int], carried: Carried | None) -> int:
        """Contacts outside ``ignore`` while the UAV makes ``move``'s turn (its fourth value,
        if any) with the arm held at ``q`` and ``carried`` in the hand, at the move's higher
        end, where :meth:`shift_base` makes it (turned low beside a cabinet, an arm reaching
        out swept through a drawer's front), every :data:`TURN_STEP` rad."""
        if len(move) < 4 or not move[3]:
            return 0
        at = np.zeros(3) if _turns_first(move) else np.asarray(move[:3])
        n = math.ceil(abs(float(move[3])) / TURN_STEP)
        data = self.loop.data
        return sum(
            len(self.ik.collisions(data, q, ignore, None, np.append(at, move[3] * k / n), carried))
            for k in range(1, n + 1)
        )

    def stow(self) -> Vec:
        """Stow the arm (:func:`stow_arm`) by a way clear of the UAV and, by
        :data:`STOW_CLEARANCE`, of everything else: straight in joint space, or through one of
        :meth:`_stow_vias` (straight, the wrist of an arm reaching out sideways swings
        through the UAV's body), with the UAV first climbing the least of :data:`CLIMBS`
        where none is clear from here (the 18 kg arm folding up fast sways the UAV: planned
        3 cm clear, the elbow swept a mug off the table beside a release). Where no way is
        clear, the straight one. Returns the climb made (m, world), for the skill to undo
        with its own UAV moves."""
        loop = self.loop
        now = arm_qpos(loop.model, loop.data)
        goal = np.asarray(c.ARM_STOW, dtype=np.float64)
        if float(np.max(np.abs(now - goal))) < STOWED_TOL:
            stow_arm(loop, loop.config.flight)
            return np.zeros(3)
        grip = gripper_target(loop.model, loop.data)

        def clear(way: list[Vec], base: Vec) -> bool:
            legs = zip([now, *way[:-1]], way, strict=True)
            return not any(
                self.path_hits(a, b, set(), grip, base, None, STOW_CLEARANCE) for a, b in legs
            )

        for climb in (np.zeros(3), *CLIMBS):
            if climb.any() and not self.flight_clear(climb):
                continue
            for way in ([goal], *([via, goal] for via in self._stow_vias(now, goal))):
                if clear(way, climb):
                    self.shift_base(climb)
                    for q in way[:-1]:
                        joint_move(loop, q, loop.config.flight.stow_s)
                    stow_arm(loop, loop.config.flight)
                    return climb
        stow_arm(loop, loop.config.flight)
        return np.zeros(3)

    @staticmethod
    def _stow_vias(now: Vec, goal: Vec) -> list[Vec]:
        """Postures to stow through: the wrist folded first, the base joint turned last, or
        the base joint turned first."""
        wrist = now.copy()
        wrist[4:] = goal[4:]
        fold = goal.copy()
        fold[0] = now[0]
        turn = now.copy()
        turn[0] = goal[0]
        return [wrist, fold, turn]

    def carry(self, delta: Vec, speed: float) -> None:
        """Fly the UAV by ``delta`` (m, world) at ``speed`` with the arm's targets held, so
        the hand moves with the base (pushing, or pulling a drawer, farther than the arm
        reaches)."""
        flight = self.loop.config.flight
        slow = flight.model_copy(update={"speed": min(speed, flight.speed), "accel": 0.25})
        target = np.array(self.loop.controller.setpoint) + np.asarray(delta)
        fly_to(self.loop, target, slow)

    def preview_line(self, start: Vec, end: Vec, rotation: Vec, seconds: float) -> list[Vec] | None:
        """The postures :meth:`line` (without ``q_end``) would command from the arm's posture
        now, one per control step, solved offline; ``None`` where IK loses the line."""
        steps = _steps(seconds)
        return self._preview([(start + (end - start) * s, rotation) for s in steps])

    def steady_line(
        self,
        start: Vec,
        end: Vec,
        rotation: Vec,
        seconds: float,
        max_speed: float,
        margin: float = MIN_MARGIN,
    ) -> list[Vec] | None:
        """:meth:`preview_line`'s postures where IK follows the whole line with no joint
        faster than ``max_speed`` (rad/s) and none within ``margin`` (rad) of its limit,
        else ``None``: near a singularity a straight line whips a joint round, and a servo at
        its limit strays off the line (either flings what the hand holds)."""
        postures = self.preview_line(start, end, rotation, seconds)
        if postures is None:
            return None
        q = np.array([arm_qpos(self.loop.model, self.loop.data), *postures])
        if float(np.max(np.abs(np.diff(q, axis=0)))) / c.CONTROL_DT > max_speed:
            return None
        if self._near_limit(postures, margin):
            return None
        return postures

    def glide(self, end: Vec, rotation: Vec, seconds: float, gripper: float, q_end: Vec) -> bool:
        """Carry the hand (pointing down) in a straight line from where it is to ``end``,
        turning it about the vertical to ``rotation`` on the way and pulling the posture
        towards ``q_end``: a joint-space move between two top-down postures tilts the hand
        midway, and a bottle held by its cap swings out of the fingers. Previewed first with
        the held object carried; ``False``, nothing moved, where IK loses the path, a joint
        would reach its limit or something would be touched."""
        start, now_rot = self.tcp()
        if now_rot[2, 2] > -0.99 or rotation[2, 2] > -0.99:  # not pointing down
            return False
        h0 = math.atan2(now_rot[1, 0], now_rot[0, 0])
        turn = math.remainder(math.atan2(rotation[1, 0], rotation[0, 0]) - h0, 2 * math.pi)
        steps = _steps(seconds)
        poses = [(start + (end - start) * s, top_down_rotation(h0 + turn * s)) for s in steps]
        q0 = arm_qpos(self.loop.model, self.loop.data)
        rests = [q0 + (q_end - q0) * s for s in steps]
        path = self._preview(poses, rests)
        if path is None or self._near_limit(path, GLIDE_MARGIN):
            return False  # at a limit, the servo strays off the line
        carried = self.carried()
        zero = np.zeros(3)
        checked = [*path[:: max(1, len(steps) // 10)], path[-1]]
        if any(
            self.ik.collisions(self.loop.data, p, set(), gripper, zero, carried) for p in checked
        ):
            return False
        return self.follow(poses, gripper, rests)

    def _near_limit(self, postures: Sequence[Vec], margin: float) -> bool:
        """Whether a joint comes within ``margin`` (rad) of its limit in one of ``postures``."""
        return min(self.ik.limit_margin(p) for p in postures) < margin

    def _preview(
        self,
        poses: Sequence[tuple[Vec, Vec]],
        postures: Sequence[Vec] | None = None,
        q0: Vec | None = None,
        base: Vec | None = None,
    ) -> list[Vec] | None:
        """The postures :meth:`follow` would command through ``poses`` (pulled towards
        ``postures``), solved offline from the posture now (or ``q0``, with the UAV moved by
        ``base``); ``None`` where IK loses them."""
        data = self.loop.data
        q = arm_qpos(self.loop.model, data) if q0 is None else q0
        out = []
        for i, (point, rotation) in enumerate(poses):
            rest = postures[i] if postures is not None else None
            q, res = self.ik.solve(data, point, rotation, q, iterations=60, base=base, posture=rest)
            if res > 3 * IK_OK:
                return None
            out.append(q)
        return out

    def line_path(
        self,
        q0: Vec,
        start: Vec,
        end: Vec,
        rotation: Vec,
        q_end: Vec,
        base: Vec,
        seconds: float,
    ) -> list[Vec] | None:
        """The postures :meth:`line` (with ``q_end``) commands from posture ``q0``, the UAV
        moved by ``base``; ``None`` where IK loses the line."""
        steps = _steps(seconds)
        poses = [(start + (end - start) * s, rotation) for s in steps]
        return self._preview(poses, [q0 + (q_end - q0) * s for s in steps], q0, base)

    def line(
        self,
        start: Vec,
        end: Vec,
        rotation: Vec,
        seconds: float,
        gripper: float,
        q_end: Vec | None = None,
    ) -> bool:
        """Move the TCP along the straight line ``start`` → ``end`` (minimum-jerk timing)
        keeping ``rotation``; ``False`` where IK loses the line. With ``q_end`` (the planned
        joint angles at ``end``), IK's posture follows the joint-space blend towards them, so
        the arm stays on the branch the plan checked for collisions."""
        q0 = arm_qpos(self.loop.model, self.loop.data)
        steps = _steps(seconds)
        poses = ((start + (end - start) * s, rotation) for s in steps)
        if q_end is None:
            return self.follow(poses, gripper)
        return self.follow(poses, gripper, (q0 + (q_end - q0) * s for s in steps))

    def follow(
        self,
        poses: Iterable[tuple[Vec, Vec]],
        gripper: float,
        postures: Iterable[Vec] | None = None,
    ) -> bool:
        """Servo the TCP through ``poses`` (position, orientation), one per control step,
        each solved from the last (and pulled towards ``postures``, one per pose, if given);
        ``False`` (stopping there) where IK loses the path."""
        loop = self.loop
        q = arm_qpos(loop.model, loop.data)
        rests = iter(postures) if postures is not None else None
        for point, rotation in poses:
            rest = next(rests) if rests is not None else None
            q, res = self.ik.solve(loop.data, point, rotation, q, iterations=60, posture=rest)
            if res > 3 * IK_OK:
                return False
            set_arm_targets(loop.model, loop.data, q, gripper)
            loop.control_step()
        return True

    def tcp(self) -> tuple[Vec, Vec]:
        """The TCP's position and orientation now (world)."""
        site = self.loop.data.site(c.TCP_SITE)
        return np.array(site.xpos), np.array(site.xmat).reshape(3, 3)

    def touching(self, geoms: set[int]) -> bool:
        """Whether both fingers touch one of ``geoms``."""
        return all(self.in_contact(fingers, geoms) for fingers in self._fingers.values())

    def in_contact(self, geoms: set[int], others: set[int]) -> bool:
        """Whether one of ``geoms`` touches one of ``others`` now."""
        d = self.loop.data
        for i in range(d.ncon):
            g1, g2 = int(d.contact.geom[i][0]), int(d.contact.geom[i][1])
            if (g1 in geoms and g2 in others) or (g2 in geoms and g1 in others):
                return True
        return False

    def outward_axis(self, body: str) -> Vec:
        """``body``'s x axis made horizontal and unit (a cabinet's front normal), world."""
        axis: Vec = np.array(self.loop.data.body(body).xmat).reshape(3, 3)[:, 0]
        axis[2] = 0.0
        return axis / float(np.linalg.norm(axis))

    def body_geoms(self, body: str) -> set[int]:
        """Geoms of ``body`` and its children."""
        return set(subtree_geoms(self.loop.model, self.loop.model.body(body).id))

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        return self.touching(self.body_geoms(obj))


def _turns_first(move: Vec) -> bool:
    """Whether :meth:`Arm.shift_base` turns the UAV (``move``'s fourth value) before flying
    ``move``'s way: for a descent, so the turn is made at the move's higher end."""
    return bool(move[2] < 0.0)


def _steps(seconds: float) -> list[float]:
    """Minimum-jerk progress at each control step of a ``seconds``-long motion (at least 2)."""
    n = max(2, round(seconds / c.CONTROL_DT))
    return [min_jerk(i / n) for i in range(1, n + 1)]
