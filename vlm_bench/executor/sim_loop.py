"""The simulation loop: physics at 400 Hz, the UAV controller at 200 Hz, control at 20 Hz.

Skills drive the robot through :meth:`SimLoop.control_step`: they set servo targets and the UAV
setpoint, then advance one control period. The loop watches for numerical blow-ups (the only
exception the executor raises internally; it becomes a failed result) and records contacts
between the robot and the rest of the world.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

import mujoco
import numpy as np

from vlm_bench.sim.constants import CONTROL_DT, STEPS_PER_CONTROL, TCP_SITE, UAV_FREEJOINT
from vlm_bench.sim.mujoco_log import route_mujoco_log
from vlm_bench.sim.robot import robot_geom_ids
from vlm_bench.sim.scene import Scene
from vlm_bench.types.episode import Episode, UavPose
from vlm_bench.types.execution import ExecutorConfig, SkillFailure
from vlm_bench.types.plan import ArmStep

UNSTABLE = "simulator unstable"
# MuJoCo resets the state itself when it meets non-finite values; these warnings tell us it did.
_BAD_STATE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADQVEL,
    mujoco.mjtWarning.mjWARN_BADQACC,
)


class SimulatorUnstable(RuntimeError):
    """The state became non-finite or absurdly fast; the executor turns it into a failure."""


class SimBudgetSpent(RuntimeError):
    """Simulated time passed :attr:`SimLoop.deadline`; the executor turns it into a failure."""


class SimLoop:
    """Steps a scene at the benchmark's rates and records robot–world contacts.

    Args:
        scene: A compiled episode scene (see :func:`vlm_bench.sim.scene.build_scene`).
        config: Executor settings.
    """

    def __init__(self, scene: Scene, config: ExecutorConfig | None = None) -> None:
        route_mujoco_log()  # an unstable simulation is logged, never MUJOCO_LOG.TXT in the cwd
        self.scene = scene
        self.model = scene.model
        self.data = scene.data
        self.controller = scene.controller
        self.config = config or ExecutorConfig()
        self._robot_geom = np.zeros(self.model.ngeom, dtype=bool)
        self._robot_geom[robot_geom_ids(self.model)] = True
        self._touched: set[int] = set()
        self._contacts_seen = b""
        """The contact pairs :meth:`_record_contacts` last recorded (as bytes)."""
        uav = self.model.joint(UAV_FREEJOINT)
        self._uav_qpos = int(uav.qposadr[0])
        self._uav_dof = int(uav.dofadr[0])
        self._bad_warnings = self._count_bad_warnings()
        self._tcp = int(self.model.site(TCP_SITE).id)
        self.held: str | None = None
        """The object the gripper holds (set by the grasping skills)."""
        self.observers: list[Callable[[SimLoop], None]] = []
        """Called after every control step (video recorders, policies' logs)."""
        self._watch: _Watch | None = None
        self.deadline: float | None = None
        """Simulated time (s) after which a control step raises :class:`SimBudgetSpent`."""

    def _count_bad_warnings(self) -> int:
        counts = self.data.warning.number.tolist()  # one array read, not one struct per kind
        return sum(counts[int(w)] for w in _BAD_STATE_WARNINGS)

    # ---- stepping ---------------------------------------------------------------------
    def physics_step(self) -> None:
        """One physics step (``PHYSICS_DT``) with the UAV controller applied."""
        self.controller.apply(self.data)
        mujoco.mj_step(self.model, self.data)
        self._record_contacts()

    def control_step(self) -> None:
        """Advance one 50 ms control period (:meth:`physics_step` 20 times, its calls looked up
        once); raises :class:`SimulatorUnstable` on blow-up and :class:`SimBudgetSpent` past
        the deadline."""
        apply, step, record = self.controller.apply, mujoco.mj_step, self._record_contacts
        model, data = self.model, self.data
        for _ in range(STEPS_PER_CONTROL):
            apply(data)
            step(model, data)
            record()
        self._check_stable()
        if self.deadline is not None and self.data.time > self.deadline:
            raise SimBudgetSpent(f"simulated time budget spent ({self.deadline:.0f} s)")
        if self._watch is not None:
            self._watch.update(self)
        for observer in self.observers:
            observer(self)

    def hold(self, seconds: float) -> None:
        """Advance ``seconds`` with the current servo targets and UAV setpoint."""
        for _ in range(max(1, round(seconds / CONTROL_DT))):
            self.control_step()

    # ---- interaction measurements (for S_arm) -------------------------------------------
    def watch(self, lo: np.ndarray, hi: np.ndarray) -> None:
        """Start tracking the closest approach to the box [lo, hi] of the TCP, or of the held
        object's centre while something is held (a point is a box with lo == hi)."""
        self._watch = _Watch(np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64))
        self._watch.update(self)

    def unwatch(self) -> tuple[float | None, float | None, float | None]:
        """Stop tracking: (initial distance, closest distance, TCP tilt there in degrees)."""
        w, self._watch = self._watch, None
        if w is None:
            return None, None, None
        return w.initial, w.best, w.tilt_deg

    def effector_point(self) -> np.ndarray:
        """Centre of the held object, or the TCP when nothing is held (m, world)."""
        if self.held is not None:
            return np.array(self.data.body(self.held).xipos, dtype=np.float64)
        return np.array(self.data.site_xpos[self._tcp], dtype=np.float64)

    def tcp_tilt_deg(self) -> float:
        """Angle between the TCP's approach axis (z) and world down (deg)."""
        zz = float(self.data.site_xmat[self._tcp][8])
        return math.degrees(math.acos(max(-1.0, min(1.0, -zz))))

    def _check_stable(self) -> None:
        """Raise :class:`SimulatorUnstable` on a new bad-state warning, a non-finite position or
        velocity, or a speed over ``max_speed_unstable``: the largest speed is NaN where a
        velocity is NaN and inf where one is infinite, so one comparison tests both."""
        d = self.data
        if self._count_bad_warnings() > self._bad_warnings:
            raise SimulatorUnstable(UNSTABLE)
        if not np.isfinite(d.qpos).all():
            raise SimulatorUnstable(UNSTABLE)
        if not np.abs(d.qvel).max(initial=0.0) <= self.config.max_speed_unstable:
            raise SimulatorUnstable(UNSTABLE)

    def _record_contacts(self) -> None:
        if not self.data.ncon:
            return
        geoms = self.data.contact.geom
        key = geoms.tobytes()
        if key == self._contacts_seen:
            return  # the previous step's contacts (objects at rest): recorded then
        self._contacts_seen = key
        robot = self._robot_geom[geoms]
        mixed = robot[:, 0] != robot[:, 1]
        if mixed.any():
            pairs = geoms[mixed]
            others = np.where(robot[mixed][:, 0], pairs[:, 1], pairs[:, 0])
            self._touched.update(int(g) for g in others)

    def take_collisions(self) -> tuple[str, ...]:
        """Names of non-robot geoms touched since the last call (then forgets them)."""
        names = sorted(
            mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom{g}"
            for g in self._touched
        )
        self._touched.clear()
        self._contacts_seen = b""
        return tuple(names)

    # ---- state ------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return float(self.data.time)

    def uav_position(self) -> np.ndarray:
        """UAV body position (m, world)."""
        return np.array(self.data.qpos[self._uav_qpos : self._uav_qpos + 3], dtype=np.float64)

    def uav_speed(self) -> float:
        """UAV linear speed (m/s)."""
        v = self.data.qvel[self._uav_dof : self._uav_dof + 3]
        return float(np.linalg.norm(v))

    def uav_yaw_deg(self) -> float:
        """UAV heading (deg, CCW from world +x)."""
        w, x, y, z = (float(v) for v in self.data.qpos[self._uav_qpos + 3 : self._uav_qpos + 7])
        return math.degrees(math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))

    def uav_pose(self) -> UavPose:
        """Current UAV pose."""
        p = self.uav_position()
        return UavPose(pos=(float(p[0]), float(p[1]), float(p[2])), yaw_deg=self.uav_yaw_deg())


class _Watch:
    def __init__(self, lo: np.ndarray, hi: np.ndarray) -> None:
        self.lo = lo
        self.hi = hi
        self.initial: float | None = None
        self.best: float | None = None
        self.tilt_deg: float | None = None

    def update(self, loop: SimLoop) -> None:
        p = loop.effector_point()
        d = float(np.linalg.norm(p - np.clip(p, self.lo, self.hi)))
        if self.initial is None:
            self.initial = d
        if self.best is None or d < self.best:
            self.best = d
            self.tilt_deg = loop.tcp_tilt_deg()


class Skill(Protocol):
    """An ARM skill bound to one loop (docs/design.md#arm-skills): runs ``step`` of
    ``episode`` on its loop and returns ``None`` on success, else its typed failure.

    Every scripted family (:mod:`vlm_bench.executor.skills`) and the policy-driven skills of
    :mod:`vlm_bench.vla.hierarchical` implement it; a factory binds them to a loop.
    """

    def __call__(self, episode: Episode, step: ArmStep, /) -> SkillFailure | None: ...
