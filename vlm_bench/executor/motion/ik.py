"""Inverse kinematics of the arm's TCP with mink, on a robot-only model.

The solver works on a separate model holding only the arm's 7 joints: the UAV is a mocap body
placed at the scene's current base pose (or where a planned base move would take it) and the
fingers are rigid, so the QP has exactly the arm's 7 unknowns and no equality constraints (the
same solutions as freezing the UAV's and fingers' dofs of the full robot, at about half the
cost per iteration). A top-down target fixes the TCP's z axis to world
−z and its x axis to a horizontal heading. The hanging arm reaches down "elbow-up"; a low-cost
posture task pulls solutions towards the seed (by default a known top-down posture).

Collision checks of candidate solutions are :mod:`~vlm_bench.executor.motion.collision_check`'s.
"""

from __future__ import annotations

import math

import mink
import mujoco
import numpy as np

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.ik_qp import IkQp
from vlm_bench.sim.constants import ARM_JOINTS, TCP_SITE, UAV_BODY, UAV_FREEJOINT
from vlm_bench.sim.robot import add_aerial_manipulator
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import UavPose

TOP_DOWN_SEED = (-1.5, -1.76, 1.6, -2.54, -1.44, 1.71, 2.8)  # a known top-down grasp posture
SEED_POSTURES = (
    TOP_DOWN_SEED,
    (-1.01, -1.75, 1.32, -3.03, -1.8, 1.78, 1.68),  # top-down, 0.6 m below and 0.6 m out
    (2.14, -1.74, 1.32, -3.03, -1.8, 1.77, 0.11),  # the same, reaching to the other side
)
"""Postures IK restarts from when the given seed does not converge (from a reach scan)."""
POS_TOL = 0.004  # m
ROT_TOL = 0.03  # rad
DT = 0.1  # s, integration step of mink's velocity solution
DAMPING = 1e-3  # Levenberg-Marquardt damping of every dof
STALL_AFTER = 20
"""Iterations a solve always gets before it may give up where it stalls."""
STALL_WINDOW = 10
STALL_GAIN = 0.05
"""A solve stalls when its lowest residual fell by less than this fraction in the last
:data:`STALL_WINDOW` iterations: most iterations go to solves that never converge, and the
planner's other starts find the rare posture a stalled solve gives up on (measurements:
``docs/decisions.md``)."""
STALL = (STALL_AFTER, STALL_WINDOW)
"""The stall rule of a solve (iterations before it may stall, the window judged)."""
CANDIDATE_STALL = (12, 6)
"""The stall rule of the planner's candidate solves (:class:`ArmPlanner`), which have other
starts to find what one gives up on: three in four of their iterations went to solves that
fail (``docs/decisions.md``). A line's steps keep :data:`STALL`: they have no other start."""


def _norm(x: FloatArray) -> float:
    """``np.linalg.norm(x)`` of a vector, computed as it does (the square root of
    ``x.dot(x)``) without its generic dispatch."""
    return math.sqrt(float(x.dot(x)))


def stalled(best: list[float], rule: tuple[int, int] = STALL) -> bool:
    """Whether a solve whose lowest residuals so far, per iteration, are ``best`` stalls
    under ``rule`` (iterations before it may, window; see :data:`STALL_GAIN`)."""
    n, (after, window) = len(best), rule
    return n > after and best[-1] > (1.0 - STALL_GAIN) * best[n - 1 - window]


def _arm_model() -> mujoco.MjModel:
    """The aerial manipulator with the UAV as a mocap body and rigid fingers: 7 dofs."""
    spec = mujoco.MjSpec()
    add_aerial_manipulator(spec, UavPose(pos=(0.0, 0.0, 1.0), yaw_deg=0.0))
    spec.body(UAV_BODY).mocap = True
    dropped = {j.name for j in spec.joints if j.name not in ARM_JOINTS}
    dropped |= {t.name for t in spec.tendons}
    for actuator in list(spec.actuators):
        if actuator.target in dropped:
            spec.delete(actuator)
    for element in [*spec.equalities, *spec.tendons]:
        spec.delete(element)
    for joint in [j for j in spec.joints if j.name in dropped]:
        spec.delete(joint)
    return spec.compile()


def top_down_rotation(heading_rad: float) -> FloatArray:
    """TCP orientation pointing down with its x axis along ``heading_rad``."""
    ch, sh = math.cos(heading_rad), math.sin(heading_rad)
    return np.array([[ch, sh, 0.0], [sh, -ch, 0.0], [0.0, 0.0, -1.0]])


def frontal_rotation(normal: FloatArray, fingers_up: bool = True) -> FloatArray:
    """TCP orientation approaching a vertical surface with outward ``normal`` (horizontal):
    the approach axis (z) points into the surface and the fingers close vertically (y axis
    along world ±z), to grasp a horizontal bar."""
    n = np.asarray(normal, dtype=np.float64)
    z = -n / np.linalg.norm(n)
    y = np.array([0.0, 0.0, 1.0 if fingers_up else -1.0])
    return np.column_stack([np.cross(y, z), y, z])


class ArmIk:
    """IK solver for one scene's arm.

    Args:
        model: The scene's compiled model (read for the arm's joint addresses and limits).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.scratch = mujoco.MjData(model)
        self._ik_state = b""
        self._solves: dict[tuple[object, ...], tuple[FloatArray, float]] = {}
        """Solves for the UAV pose ``_ik_state`` (the planner repeats ~10 % exactly)."""
        self.qadr = np.array([model.joint(j).qposadr[0] for j in ARM_JOINTS])
        self.lo = np.array([model.joint(j).range[0] for j in ARM_JOINTS]) + 0.01
        self.hi = np.array([model.joint(j).range[1] for j in ARM_JOINTS]) - 0.01
        self.site = int(model.site(TCP_SITE).id)
        self._uav_qadr = int(model.joint(UAV_FREEJOINT).qposadr[0])
        # The arm-only model mink solves on (its qpos is the 7 arm angles, in ARM_JOINTS order).
        self.robot = _arm_model()
        self._r_qadr = np.array([self.robot.joint(j).qposadr[0] for j in ARM_JOINTS])
        self.config = mink.Configuration(self.robot)
        self.frame = mink.FrameTask(
            TCP_SITE, "site", position_cost=1.0, orientation_cost=0.5, lm_damping=1e-3
        )
        self.posture = mink.PostureTask(self.robot, cost=1e-3)
        self.limits = [mink.ConfigurationLimit(self.robot)]
        self.qp = IkQp(self.config, self.frame, self.posture, self.limits[0], DAMPING)
        """Each iteration's QP (``mink.solve_ik``'s numbers, assembled faster)."""

    def _load(self, data: mujoco.MjData, q: FloatArray, base: BaseMove | None) -> None:
        """Arm-model configuration: the UAV (mocap) at the scene's UAV pose moved by ``base``,
        the arm at angles ``q``."""
        uav = np.array(data.qpos[self._uav_qadr : self._uav_qadr + 7])
        if base is not None:
            base.apply(uav, 0)
        self.config.data.mocap_pos[0] = uav[:3]
        self.config.data.mocap_quat[0] = uav[3:]
        qpos = self.config.q.copy()
        qpos[self._r_qadr] = q
        self.config.update(qpos)

    def solve(
        self,
        data: mujoco.MjData,
        pos: FloatArray,
        rotation: FloatArray,
        seed: FloatArray,
        iterations: int = 200,
        base: BaseMove | None = None,
        posture: FloatArray | None = None,
        stall: tuple[int, int] = STALL,
    ) -> tuple[FloatArray, float]:
        """Joint angles putting the TCP at ``pos`` with orientation ``rotation`` (3×3, world;
        see :func:`top_down_rotation`), with the UAV where it is (or moved by ``base``, m, to
        plan a base adjustment). A weak posture task pulls towards ``posture`` (default: the
        seed), which picks the branch among the arm's redundant solutions.

        Returns the solution and its residual (position error in m plus rotation error in
        rad); the caller decides whether it is good enough. A solve of more iterations than
        ``stall`` allows before it may stall gives up where it stalls (:func:`stalled`). The
        planner repeats ~10 % of its solves exactly: those are answered from a cache that
        holds while the UAV does not move.
        """
        uav = data.qpos[self._uav_qadr : self._uav_qadr + 7].tobytes()
        if uav != self._ik_state:
            self._ik_state = uav
            self._solves.clear()
        arrays = (pos, rotation, seed, posture)
        key = (
            iterations,
            stall,
            *(None if a is None else np.asarray(a, np.float64).tobytes() for a in arrays),
            None if base is None else base.key(),
        )
        hit = self._solves.get(key)
        if hit is None:
            hit = self._solve(data, pos, rotation, seed, iterations, base, posture, stall)
            self._solves[key] = hit
        return hit[0].copy(), hit[1]

    def _solve(
        self,
        data: mujoco.MjData,
        pos: FloatArray,
        rotation: FloatArray,
        seed: FloatArray,
        iterations: int,
        base: BaseMove | None,
        posture: FloatArray | None,
        stall: tuple[int, int],
    ) -> tuple[FloatArray, float]:
        """:meth:`solve` computed (no cache)."""
        q0 = np.clip(np.asarray(seed, dtype=np.float64), self.lo, self.hi)
        self._load(data, q0, base)
        target = mink.SE3.from_rotation_and_translation(
            mink.SO3.from_matrix(np.asarray(rotation)), np.asarray(pos)
        )
        self.frame.set_target(target)
        rest = self.config.q.copy()
        if posture is not None:
            rest[self._r_qadr] = np.clip(posture, self.lo, self.hi)
        self.posture.set_target(rest)
        residual = math.inf
        best: list[float] = []  # the lowest residual so far, per iteration
        for _ in range(iterations):
            err = self.frame.compute_error(self.config)
            e_pos, e_rot = _norm(err[:3]), _norm(err[3:])
            residual = e_pos + e_rot
            if e_pos < POS_TOL and e_rot < ROT_TOL:
                break
            best.append(min(residual, best[-1]) if best else residual)
            if iterations > stall[0] and stalled(best, stall):
                break
            self.config.integrate_inplace(self.qp.velocity(err, DT), DT)
        q = np.clip(self.config.q[self._r_qadr], self.lo, self.hi)
        if not np.array_equal(q, self.config.q[self._r_qadr]):  # the residual of what is returned
            qpos = self.config.q.copy()
            qpos[self._r_qadr] = q
            self.config.update(qpos)
            err = self.frame.compute_error(self.config)
            residual = float(np.linalg.norm(err[:3])) + float(np.linalg.norm(err[3:]))
        return q, residual

    def _pose(
        self, s: mujoco.MjData, data: mujoco.MjData, q: FloatArray, base: BaseMove | None
    ) -> None:
        """Scratch ``s`` set to the scene's state with arm angles ``q`` (UAV moved by
        ``base``); kinematics not yet run."""
        s.qpos[:] = data.qpos
        if base is not None:
            base.apply(s.qpos, self._uav_qadr)
        s.qpos[self.qadr] = q

    def tcp_at(
        self, data: mujoco.MjData, q: FloatArray, base: BaseMove | None = None
    ) -> FloatArray:
        """Where the TCP would be with arm angles ``q`` (UAV moved by ``base``), world."""
        self._pose(self.scratch, data, q, base)
        mujoco.mj_kinematics(self.model, self.scratch)
        return np.array(self.scratch.site_xpos[self.site])

    def room(self, q: FloatArray) -> FloatArray:
        """Each joint's distance in ``q`` from its nearer (inset) limit (rad)."""
        return np.minimum(q - self.lo, self.hi - q)

    def limit_margin(self, q: FloatArray) -> float:
        """Smallest distance of ``q`` from the (inset) joint limits (rad)."""
        return float(np.min(self.room(q)))
