"""Scripted top-down ``pick`` and ``place`` with IK and real contact physics (no welds).

Pick: open, move (joint-space, minimum-jerk) to a pre-grasp 0.12 m above the object with the
hand pointing down, descend along a straight line, close, lift 0.15 m. It succeeds only if both
fingers touch the object and the object has risen. Place: move above the destination, lower,
open, retreat up and stow.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world import object_kind
from vlm_bench.episodes.layout import CONTAINER_FLOOR
from vlm_bench.executor.arm import Arm, Reach
from vlm_bench.executor.grasp_points import grasp_points
from vlm_bench.executor.ik import TOP_DOWN_SEED, top_down_rotation
from vlm_bench.executor.loop import ArmSkill, SimLoop
from vlm_bench.executor.motion import HELD_JOINT_SPEED, hold_with_gripper, joint_move
from vlm_bench.sim import constants as c
from vlm_bench.sim.constants import part_joint
from vlm_bench.sim.objects.bounds import geom_bounds, object_bounds, subtree_geoms
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.world import ObjectKind

Vec = NDArray[np.float64]
PRE_GRASP = 0.12  # m above the grasp point
LIFT = 0.15  # m
MIN_LIFT = 0.08  # m the object must rise for a pick to count
CARRY_DEPTH = 0.30  # m below the arm base: a held object's TCP height in flight
SECTION_HALF = 0.025  # m along the hand: geoms centred this near make the grasped section
HAND_HALF = 0.105  # m: half the Panda hand's length, along its fingers' closing axis
PLACE_CLEARANCE = 0.01  # m: a way down to a release keeping this clear of the rest is preferred
GLIDE_TOL = 0.2  # rad: a descent planned after a glide must start this close to its end
GRASP_DESCENT = 1.5  # s: the hand's straight way down onto a grasp point
GRASP_TURN_ROOM = 0.15  # rad: a grasp posture with the base joint nearer its limit counts as a
# contact (the lift and raise of a can grasped 0.09 rad off it took it to 0.02, and no way to
# the bowl beside it was left but a swing that flung the can)
CARRY_SPEED = 0.15  # m/s: mean speed of the hand carrying an object to above its release
RAISE_JOINT_SPEED = 1.0  # rad/s: the fastest joint the straight raise to carry may need...
RAISE_MARGIN = 0.01  # rad: ...and the nearest it may come to its limit (0: at IK's clamp)
TALL = 2.0  # height over the narrowest side of the base: such an object is set down, not dropped
SET_DOWN = 0.04  # m the hand lowers a tall object at most, from its release, to set it down
SET_DOWN_STEP = 0.005  # m the hand lowers it per 0.1 s until it touches
CENTRE_TOL = 0.001  # m: a tall object's middle is brought this close over its resting place...
CENTRE_TRIES = 3  # ...in at most this many sideways moves of the hand, before it is set down
RAISE_SWING = 1.0  # rad: the widest joint swing of a joint-space raise with an object in hand
SLIP = 0.03  # m a held object may move in the hand on the way to its release while out of
# one finger's touch (set down on its destination, a tall bottle pushes up between the pads)
RETREAT = 0.12  # m: the open hand rises at least this far after a release
RELEASE_TOL = 0.06  # m: the TCP must come this close to the release point (an arm stretched
# a metre down into a drawer sags 4 cm; farther off, it did not get there)
DRAWER_DROP_SIZE = 0.1  # m: the widest object dropped into a drawer from above its front
DRAWER_OUT = (0.36, 0.46)  # m, horizontal: arm base in front of a drawer release point
DRAWER_DEPTHS = (1.0, 0.9)  # m: arm base above it (from a reach scan over an open drawer)
DRAWER_TURNS = (math.pi, math.pi / 2, -math.pi / 2)  # rad: UAV heading turns tried last there


class Grasper:
    """Pick and place for one scene (what is held lives in ``loop.held``)."""

    def __init__(self, loop: SimLoop, arm: Arm | None = None) -> None:
        self.loop = loop
        self.arm = arm or Arm(loop)

    def _plan_top_down(
        self,
        point: Vec,
        approach: Vec,
        yaw_rad: float,
        ignore: set[int],
        gripper: float,
        seed: Vec,
        assist: list[Vec] | None = None,
    ) -> Reach | None:
        """The top-down motion from ``point + approach`` down to ``point``, over the four
        headings equivalent for a box-like object (or a held one), preferring those that keep
        :data:`PLACE_CLEARANCE` from the rest."""
        rotations = [top_down_rotation(yaw_rad + k * math.pi / 2) for k in range(4)]
        return self.arm.plan(
            point, approach, rotations, ignore, gripper, seed, assist, PLACE_CLEARANCE
        )

    def _plan_grasp(self, obj: str, kind: ObjectKind) -> tuple[Reach, Vec] | None:
        """The descent onto a grasp point, and the point: the first of the object's grasp
        points the hand reaches touching nothing else, else the best one."""
        loop = self.loop
        lo, hi = object_bounds(loop.model, loop.data, obj, solid_only=True)
        body = loop.data.body(obj)
        rot = body.xmat.reshape(3, 3)
        yaw = math.atan2(rot[1, 0], rot[0, 0])
        ignore = self.arm.body_geoms(obj)
        fallback = None
        com = np.array(body.xipos)
        for cand in grasp_points(kind, np.array(body.xpos), yaw, lo, hi, com):
            point = (
                self._on_section(obj, cand.point, cand.rotations[0])
                if cand.centre_across
                else cand.point
            )
            approach = np.array([0.0, 0.0, PRE_GRASP])
            sol = self.arm.plan(
                point,
                approach,
                cand.rotations,
                ignore,
                c.GRIPPER_OPEN,
                np.asarray(TOP_DOWN_SEED),
                line=GRASP_DESCENT,
                turn_room=GRASP_TURN_ROOM,
            )
            if sol is None:
                continue
            if sol.hits == 0:
                return sol, point
            fallback = fallback or (sol, point)
        return fallback

    def _on_section(self, obj: str, point: Vec, rotation: Vec) -> Vec:
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

    def touching_fingers(self, obj: str) -> bool:
        """Whether both fingers touch ``obj``."""
        return self.arm.touching_fingers(obj)

    def pick(self, episode: Episode, step: ArmStep) -> str | None:
        """Top-down grasp of ``step.object``; ``None`` on success, else the reason."""
        loop, obj = self.loop, step.object
        kinds = {o.id: o.kind for o in episode.objects}
        if obj not in kinds:
            return f"unknown object {obj!r}"
        if loop.held is not None:
            return f"already holding {loop.held}"
        if not object_kind(kinds[obj]).graspable:
            return f"{obj} cannot be grasped"
        sol = self._plan_grasp(obj, object_kind(kinds[obj]))
        if sol is None:
            return f"{obj} is out of reach"
        reach, grasp = sol
        rot, shift = reach.rotation, reach.shift
        above = grasp + np.array([0.0, 0.0, PRE_GRASP])
        arm = self.arm
        arm.shift_base(shift)
        joint_move(loop, reach.q_start, 2.5, c.GRIPPER_OPEN)
        hold_with_gripper(loop, 0.3, c.GRIPPER_OPEN)
        if not arm.line(above, grasp, rot, GRASP_DESCENT, c.GRIPPER_OPEN, reach.q_end):
            return f"{obj} is out of reach"
        hold_with_gripper(loop, 0.3, c.GRIPPER_OPEN)
        hold_with_gripper(loop, 1.0, c.GRIPPER_CLOSED)
        z0 = float(loop.data.body(obj).xpos[2])
        bottom = self._bottom(obj)
        if not arm.line(grasp, grasp + np.array([0.0, 0.0, LIFT]), rot, 1.5, c.GRIPPER_CLOSED):
            return "cannot lift: out of reach"
        hold_with_gripper(loop, 0.3, c.GRIPPER_CLOSED)
        if not self.touching_fingers(obj) or loop.data.body(obj).xpos[2] - z0 < MIN_LIFT:
            return f"grasp of {obj} failed"
        loop.held = obj
        self._raise_to_carry(rot, c.GRIPPER_CLOSED)
        # Undo the UAV's move, but a climb only as far as the held object stays MIN_LIFT
        # above where it lay (lowered with the arm unable to raise it, it lands on the
        # table), and not at all where it would come down on something (a basket's rim).
        undo = -np.asarray(shift, dtype=np.float64)
        undo[2] = max(undo[2], min(0.0, bottom + MIN_LIFT - self._bottom(obj)))
        turn = arm.clear_for_flight(undo) if undo[2] < 0.0 else 0.0
        if turn is None:
            undo[2] = 0.0
        arm.shift_base(undo)
        arm.turn_back(turn)
        return None

    def _in_hand(self, obj: str) -> Vec:
        """Where ``obj`` is in the hand's frame (m)."""
        tcp, rot = self.arm.tcp()
        return rot.T @ (np.array(self.loop.data.body(obj).xpos) - tcp)

    def _bottom(self, obj: str) -> float:
        """Height of ``obj``'s lowest solid point (m)."""
        lo, _ = object_bounds(self.loop.model, self.loop.data, obj, solid_only=True)
        return float(lo[2])

    def _raise_to_carry(self, rot: Vec, gripper: float) -> None:
        """Lift the hand straight up until the TCP is :data:`CARRY_DEPTH` below the arm base
        (or as high as the arm follows). Holding an object, UAV moves carry it there rather
        than stowed, where a bulky object would be folded against the arm and knocked out of
        the fingers; empty, the stow then starts clear of what the hand just let go of."""
        arm, loop = self.arm, self.loop
        tcp, _ = arm.tcp()
        top = float(loop.data.body(c.ARM_BASE_BODY).xpos[2]) - CARRY_DEPTH
        if tcp[2] >= top:
            return
        goal = np.array([tcp[0], tcp[1], top])
        if self._raise(tcp, goal, rot, gripper):
            return
        # The straight line leaves IK's branch or whips a joint round (an arm stretched far
        # down folds up only by swinging its elbow): a checked joint-space move instead, from
        # where it stopped; holding an object, only a narrow swing (a 1.8 rad one tilted the
        # hand and flung a bolt), else half the line, else none (it stays where the pick
        # lifted it).
        held = arm.body_geoms(loop.held) if loop.held is not None else set()
        now = arm_qpos(loop.model, loop.data)
        sol = arm.plan(goal, np.zeros(3), [rot], held, gripper, now, [np.zeros(3)])
        narrow = sol is not None and float(np.max(np.abs(sol.q_end - now))) <= RAISE_SWING
        if sol is not None and sol.hits == 0 and (loop.held is None or narrow):
            joint_move(loop, sol.q_end, 1.5, gripper, HELD_JOINT_SPEED)
            return
        if loop.held is not None:
            self._raise(tcp, (tcp + goal) / 2, rot, gripper)

    def _raise(self, tcp: Vec, goal: Vec, rot: Vec, gripper: float) -> bool:
        """The straight raise from ``tcp`` to ``goal`` at :data:`CARRY_SPEED`, where it is
        steady (holding an object) and IK follows it; whether it got there."""
        arm = self.arm
        seconds = max(1.0, float(goal[2] - tcp[2]) / CARRY_SPEED)  # fast, it flings a bolt
        if self.loop.held is not None and (
            arm.steady_line(tcp, goal, rot, seconds, RAISE_JOINT_SPEED, RAISE_MARGIN) is None
        ):
            return False
        return arm.line(tcp, goal, rot, seconds, gripper)

    def place(self, episode: Episode, step: ArmStep) -> str | None:
        """Lower the held object onto/into ``step.object`` and release it."""
        loop, dest = self.loop, step.object
        held = loop.held
        if held is None:
            return "nothing held"
        if dest not in episode.object_ids():
            return f"unknown object {dest!r}"
        if not self.touching_fingers(held):
            loop.held = None
            return f"{held} slipped from the gripper"
        release = self._release_point(episode, held, dest)
        arm = self.arm
        grip = self._in_hand(held)
        tcp, rot = arm.tcp()
        clearance = max(0.0, self._top_under(dest) - (release[2] - self._hang(held))) + 0.05
        above = release + np.array([0.0, 0.0, clearance])
        heading = math.atan2(rot[1, 0], rot[0, 0])
        lift_to = np.array([tcp[0], tcp[1], max(tcp[2], above[2])])
        if not arm.line(tcp, lift_to, top_down_rotation(heading), 0.8, c.GRIPPER_CLOSED):
            # The arm cannot raise it that far on its own (folded up under the base): the
            # UAV climbs the rest, carrying it.
            arm.shift_base(np.array([0.0, 0.0, max(0.0, lift_to[2] - arm.tcp()[0][2])]))
        ignore = arm.body_geoms(held)
        sol = self._plan_top_down(
            release,
            above - release,
            heading,
            ignore,
            c.GRIPPER_CLOSED,
            arm_qpos(loop.model, loop.data),
            self._drawer_assists(episode, dest, release),
        )
        if (sol is None or sol.hits) and self._can_drop_into(episode, held, dest):
            # No clear way down inside (the hand, 0.2 m long, meets a wall or what lies
            # there already): let go just above the rim instead, and let it drop in.
            drop = release.copy()
            drop[2] = above[2] - 0.03
            high = self._plan_top_down(
                drop,
                above - drop,
                heading,
                ignore,
                c.GRIPPER_CLOSED,
                arm_qpos(loop.model, loop.data),
                self._drawer_assists(episode, dest, drop),
            )
            if high is not None and (sol is None or high.hits < sol.hits):
                sol, release = high, drop
        if sol is None:
            return f"{dest} is out of reach"
        arm.shift_base(sol.shift)
        q_start, q_end, rot, shift = self._bring_over(release, above, sol, heading, ignore)
        joint_move(loop, q_start, 2.0, c.GRIPPER_CLOSED, HELD_JOINT_SPEED)
        # Down to the release in joint space, on the path the plan checked: a long straight
        # line (into a deep drawer) can leave IK's branch and swing the forearm into a rim.
        joint_move(loop, q_end, 1.5, c.GRIPPER_CLOSED, HELD_JOINT_SPEED)
        hold_with_gripper(loop, 0.3, c.GRIPPER_CLOSED)
        moved = float(np.linalg.norm(self._in_hand(held) - grip))
        if moved > SLIP and not self.touching_fingers(held):
            loop.held = None
            return f"{held} slipped from the gripper"
        if float(np.linalg.norm(arm.tcp()[0] - release)) > RELEASE_TOL:
            return f"{dest} is out of reach"
        kind = _kind(episode, held)
        if kind is not None and kind.size[2] > TALL * min(kind.size[:2]):
            self._set_down(held, dest, release, rot)
        hold_with_gripper(loop, 0.6, c.GRIPPER_OPEN)
        loop.held = None
        retreat = max(RETREAT, float(above[2] - release[2]))  # clear of the rim before stowing
        arm.line(release, release + np.array([0.0, 0.0, retreat]), rot, 1.0, c.GRIPPER_OPEN)
        self._raise_to_carry(rot, c.GRIPPER_OPEN)
        undo = -shift  # the UAV's moves (and turn) made for the release, undone
        undo[:3] -= arm.stow()
        arm.shift_base(undo)
        return None

    def _set_down(self, held: str, dest: str, release: Vec, rot: Vec) -> None:
        """Centre ``held`` over ``release`` (:meth:`_centre_over`), then lower the hand until
        ``held`` touches ``dest``, by at most :data:`SET_DOWN`: dropped 2 cm onto a bowl's
        curved floor, a 21 cm cleanser rocked and toppled out over the rim (lowered by a fixed
        1.5 cm instead, one that already stood on the floor was pushed up in the fingers)."""
        arm = self.arm
        ours, theirs = arm.body_geoms(held), arm.body_geoms(dest)
        step = np.array([0.0, 0.0, SET_DOWN_STEP])
        point = self._centre_over(held, release, rot)
        for _ in range(round(SET_DOWN / SET_DOWN_STEP)):
            if arm.in_contact(ours, theirs):
                return
            if not arm.line(point, point - step, rot, 0.1, c.GRIPPER_CLOSED):
                return
            point = point - step

    def _centre_over(self, held: str, release: Vec, rot: Vec) -> Vec:
        """Move the hand sideways until ``held``'s middle is within :data:`CENTRE_TOL` over
        ``release`` (the resting place's centre); the TCP there. A bottle held by its cap
        hangs up to 1.5 cm off the hand's centre, and the TCP stops a few mm off its goal: a
        cleanser let go 14 mm off a bowl's centre stood a corner on the curved wall, slid,
        toppled and tipped the bowl over (its base, 9.4 cm across, just fits the 9.6 cm floor)."""
        loop, arm = self.loop, self.arm
        tcp = arm.tcp()[0]
        for _ in range(CENTRE_TRIES):
            lo, hi = object_bounds(loop.model, loop.data, held, solid_only=True)
            off = release[:2] - (lo[:2] + hi[:2]) / 2
            if float(np.linalg.norm(off)) < CENTRE_TOL:
                break
            to = tcp + np.array([off[0], off[1], 0.0])
            if not arm.line(tcp, to, rot, 0.3, c.GRIPPER_CLOSED):
                break
            hold_with_gripper(loop, 0.2, c.GRIPPER_CLOSED)  # let it stop swinging
            tcp = arm.tcp()[0]
        return tcp

    def _bring_over(
        self, release: Vec, above: Vec, sol: Reach, heading: float, ignore: set[int]
    ) -> tuple[Vec, Vec, Vec, Vec]:
        """Carry the held object to ``above`` its release, with the UAV moved by ``sol``'s
        shift already: the hand glides there pointing down (turning to the plan's heading on
        the way, or, where the arm would meet itself turning, keeping its own); else the UAV
        flies it there with the arm's posture held; else (the flight would touch something)
        nothing moves and the plan's joint-space move takes it. A joint-space move between
        two top-down postures tilts the hand midway and swings an object hanging from the
        fingers (a bottle by its cap, a teddy bear by its head) out of them.

        Returns the descent's first and last postures, the hand's orientation on it and the
        UAV's move in all (to undo after the release)."""
        arm, loop = self.arm, self.loop
        seconds = max(2.0, float(np.linalg.norm(above - arm.tcp()[0])) / CARRY_SPEED)
        now = arm_qpos(loop.model, loop.data)
        shift = np.array(sol.shift, dtype=np.float64)

        def glide(plan: Reach) -> tuple[Vec, Vec, Vec, Vec] | None:
            if not arm.glide(above, plan.rotation, seconds, c.GRIPPER_CLOSED, plan.q_start):
                return None
            # It may end on another branch: the way down planned again from there.
            way = self._descent(release, above, heading, ignore, np.zeros(3)) or plan
            return way.q_start, way.q_end, way.rotation, shift

        if (done := glide(sol)) is not None:
            return done
        # The plan's heading failed: a plan for the hand's heading now.
        keep = arm.plan(
            release,
            above - release,
            [top_down_rotation(heading)],
            ignore,
            c.GRIPPER_CLOSED,
            now,
            [np.zeros(3)],
            PLACE_CLEARANCE,
        )
        if keep is not None and not keep.hits and (done := glide(keep)) is not None:
            return done
        travel = above - arm.tcp()[0]
        down = self._descent(release, above, heading, ignore, travel)
        if down is not None and arm.flight_clear(travel):
            arm.shift_base(travel)
            # Planned again where the UAV settled (a centimetre off puts a hand in a box's wall).
            way = self._descent(release, above, heading, ignore, np.zeros(3)) or down
            shift[:3] += travel
            return way.q_start, way.q_end, way.rotation, shift
        return sol.q_start, sol.q_end, sol.rotation, shift

    def _descent(
        self, release: Vec, above: Vec, heading: float, ignore: set[int], base: Vec
    ) -> Reach | None:
        """The clear way down from ``above`` to ``release`` with the UAV moved by ``base``,
        starting within :data:`GLIDE_TOL` of the arm's posture now (the hand already above),
        if any."""
        now = arm_qpos(self.loop.model, self.loop.data)
        down = self._plan_top_down(
            release, above - release, heading, ignore, c.GRIPPER_CLOSED, now, [base]
        )
        if down is None or down.hits or np.max(np.abs(down.q_start - now)) >= GLIDE_TOL:
            return None
        return down

    def _can_drop_into(self, episode: Episode, held: str, dest: str) -> bool:
        """Whether ``held`` may be dropped into ``dest`` from above its rim: ``dest`` holds
        things inside it (a basket, a bowl, an open drawer's box for objects at most
        :data:`DRAWER_DROP_SIZE` across; not a plate) and is deeper than the object is tall (a
        tall bottle dropped in topples out over the rim)."""
        model, data = self.loop.model, self.loop.data
        kind = _kind(episode, dest)
        hlo, hhi = object_bounds(model, data, held, solid_only=True)
        if _is_vessel(kind):
            lo, hi = object_bounds(model, data, dest, solid_only=True)
            depth = float(hi[2] - lo[2]) - CONTAINER_FLOOR
        elif kind is None and any(p.id == dest and p.kind == "drawer" for p in episode.parts):
            _, wall = geom_bounds(model, data, model.geom(f"{dest}/box_front").id)
            depth = float(wall[2]) - float(data.body(dest).xpos[2])  # the floor: body origin
            if float(np.max(hhi[:2] - hlo[:2])) > DRAWER_DROP_SIZE:
                return False  # from over the front, a 0.4 m fall: a banana lands across a wall
        else:
            return False
        return float(hhi[2] - hlo[2]) < depth

    def _drawer_assists(self, episode: Episode, dest: str, release: Vec) -> list[Vec] | None:
        """For a release into an open drawer, UAV moves to hover in front of it, high: the
        drawer's tall front leaves the arm no way in across it, only down from above; then the
        usual assists; last, the hovers with the UAV turned by one of :data:`DRAWER_TURNS`.
        The base joint turns through 5.8 rad, not a full turn: facing the cabinet one way, the
        arm reached down into drawer_interaction's drawer clear of its front; facing the other,
        half a turn round, every way in met the front or folded the elbow over the cabinet.
        ``None`` (the usual assists) for other destinations."""
        part = next((p for p in episode.parts if p.id == dest and p.kind == "drawer"), None)
        if part is None:
            return None
        axis = self.arm.outward_axis(part.parent)
        base = self.loop.data.body(c.ARM_BASE_BODY).xpos
        hover = [
            np.append(release[:2] + axis[:2] * out, release[2] + depth) - base
            for depth in DRAWER_DEPTHS
            for out in DRAWER_OUT
        ]
        turned = [np.append(move, turn) for turn in DRAWER_TURNS for move in hover]
        return [*hover, *self.arm.assists(release), *turned]

    def _hang(self, held: str) -> float:
        """TCP height above the held object's bottom (m)."""
        lo, _ = object_bounds(self.loop.model, self.loop.data, held, solid_only=True)
        return float(self.loop.data.site(c.TCP_SITE).xpos[2] - lo[2])

    def _top_under(self, dest: str) -> float:
        """Top of the destination (m)."""
        _, hi = object_bounds(self.loop.model, self.loop.data, dest, solid_only=True)
        return float(hi[2])

    def _release_point(self, episode: Episode, held: str, dest: str) -> Vec:
        """TCP position that sets the held object down 2 cm above its resting place."""
        loop = self.loop
        lo, hi = object_bounds(loop.model, loop.data, dest, solid_only=True)
        kind = _kind(episode, dest)
        if _is_vessel(kind):
            rest = float(lo[2]) + CONTAINER_FLOOR
        elif kind is None:  # a drawer: its floor is the body origin's height
            rest = float(loop.data.body(dest).xpos[2])
            lo, hi = self._exposed(episode, dest, lo, hi)
        else:
            rest = float(hi[2])
        x, y = self._beside_contents(episode, dest, held, lo, hi)
        return np.array([x, y, rest + self._hang(held) + 0.02])

    def _exposed(self, episode: Episode, drawer: str, lo: Vec, hi: Vec) -> tuple[Vec, Vec]:
        """The part of an open drawer's bounds [lo, hi] out in front of its cabinet: from the
        front panel's inner face back by the opening (the rest lies under the cabinet's top,
        where no hand reaches down). The cabinet faces along a world axis (fixed furniture
        is set square)."""
        model, data = self.loop.model, self.loop.data
        parent = next(p.parent for p in episode.parts if p.id == drawer)
        axis = self.arm.outward_axis(parent)
        k = int(np.argmax(np.abs(axis[:2])))
        sign = math.copysign(1.0, float(axis[k]))
        flo, fhi = geom_bounds(model, data, model.geom(f"{drawer}/front").id)
        inner = float(flo[k] if sign > 0 else fhi[k])
        opening = float(data.qpos[model.joint(part_joint(drawer)).qposadr[0]])
        a, b = sorted((inner, inner - sign * opening))
        lo, hi = lo.copy(), hi.copy()
        lo[k], hi[k] = max(float(lo[k]), a), min(float(hi[k]), b)
        return lo, hi

    def _beside_contents(
        self, episode: Episode, dest: str, held: str, lo: Vec, hi: Vec
    ) -> tuple[float, float]:
        """Release x, y in the destination spanning [lo, hi]: its centre, or off what already
        lies there (a second object into the same basket): of a grid of points keeping the
        held object inside, the nearest to the centre where it clears the contents' boxes,
        else the one farthest from them (walls are for the hand's planning to clear)."""
        model, data = self.loop.model, self.loop.data
        boxes = []
        for o in episode.objects:
            if o.id in (dest, held):
                continue
            olo, ohi = object_bounds(model, data, o.id, solid_only=True)
            mid = (olo + ohi) / 2
            within = np.all(lo[:2] <= mid[:2]) and np.all(mid[:2] <= hi[:2])
            if within and lo[2] - 0.01 <= olo[2] < hi[2]:  # in it, not what it stands on
                boxes.append((mid[:2], float(np.max(ohi[:2] - olo[:2])) / 2))
        centre = (lo[:2] + hi[:2]) / 2
        if not boxes:
            return float(centre[0]), float(centre[1])
        hlo, hhi = object_bounds(model, data, held, solid_only=True)
        held_half = float(np.max(hhi[:2] - hlo[:2])) / 2
        half = (hi[:2] - lo[:2]) / 2
        slack = np.maximum(0.0, half - held_half - 0.02)
        # The hand, 0.2 m long, lies along the longer side: it must stay clear of the walls.
        long = int(np.argmax(half))
        slack[long] = min(slack[long], max(0.0, half[long] - HAND_HALF))
        steps = np.linspace(-1.0, 1.0, 7)
        best, best_key = centre, (-1.0, -math.inf, 0.0)
        for fx in steps:
            for fy in steps:
                p = centre + slack * np.array([fx, fy])
                room = min(float(np.linalg.norm(p - m)) - r for m, r in boxes)
                fits = room >= held_half + 0.015
                key = (float(fits), 0.0 if fits else room, -float(np.linalg.norm(p - centre)))
                if key > best_key:
                    best, best_key = p, key
        return float(best[0]), float(best[1])


def _kind(episode: Episode, obj: str) -> ObjectKind | None:
    """The catalogue kind of the episode's object ``obj`` (``None``: not an object, a part)."""
    return next((object_kind(o.kind) for o in episode.objects if o.id == obj), None)


def _is_vessel(kind: ObjectKind | None) -> bool:
    """Whether objects go inside ``kind`` (a basket, a bowl), rather than on it (a plate) or
    into a part (``None``: a drawer)."""
    return kind is not None and kind.container and not kind.support


def grasp_skills(loop: SimLoop, arm: Arm | None = None) -> dict[str, ArmSkill]:
    """``pick`` and ``place`` bound to one loop (they share what is held)."""
    grasper = Grasper(loop, arm)
    return {
        "pick": lambda _loop, episode, step: grasper.pick(episode, step),
        "place": lambda _loop, episode, step: grasper.place(episode, step),
    }
