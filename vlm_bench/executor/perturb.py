"""Perturbations a good plan cannot avoid (``--perturb``; docs/design.md#closed-loop).

``slip=P``: when a flight starts with an object in the hand, with probability P the fingers
open at a drawn moment of the flight (its end, if it is shorter) and the object drops; the
robot does not notice until a skill needs it (``place`` fails ``slipped``).
``bump=P``: before an ARM step, with probability P its object (a free, movable object that is
not held) is displaced 0.2-0.4 m in a drawn horizontal direction, staying on what it rests on
and clear of other objects; objects resting on it move with it. Where no direction keeps it so
(tried every 45 degrees from the drawn one), nothing is displaced.

Each kind draws from its own stream, seeded per episode, and draws the same numbers whether or
not its event fires, so an episode meets the same events in every run, and the events of one
kind do not depend on the other kind's setting.
"""

from __future__ import annotations

import hashlib
import math

import mujoco
import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.motion.joint_moves import hold_with_gripper
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import (
    GRIPPER_ACTUATOR,
    GRIPPER_OPEN,
    LEFT_FINGER_BODY,
    RIGHT_FINGER_BODY,
)
from vlm_bench.sim.objects.bounds import object_bounds, subtree_geoms
from vlm_bench.types.closed_loop import PerturbConfig, PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep

BUMP_RANGE = (0.2, 0.4)
"""Horizontal displacement of a bump (m)."""
SLIP_WINDOW_S = (0.3, 2.0)
"""Flight time at which a slip drops the object (s)."""
DROP_S = 0.6
"""Time the open fingers are held after a drop at a flight's end (s)."""
_SUPPORT_PROBE = 0.02  # m below an object's bottom: what it rests on is hit within this
_CLEARANCE = 0.005  # m: a displaced object may not come closer than this to another


def perturb_seed(task_id: str, seed: int, kind: str) -> int:
    """Seed of one kind's stream for an episode (shared by both instruction variants)."""
    digest = hashlib.sha256(f"perturb|{kind}|{task_id}|{seed}".encode()).digest()
    return int.from_bytes(digest[:8], "big")


class Perturber:
    """Fires the episode's perturbations on one loop and keeps those that fired."""

    def __init__(self, config: PerturbConfig, episode: Episode) -> None:
        self.config = config
        self.episode = episode
        self._slip = np.random.default_rng(perturb_seed(episode.task_id, episode.seed, "slip"))
        self._bump = np.random.default_rng(perturb_seed(episode.task_id, episode.seed, "bump"))
        self.events: list[PerturbEvent] = []
        self._drop_at: float | None = None
        self._flight_start = 0.0
        self._step = 0

    # ---- slip -------------------------------------------------------------------------
    def flight_started(self, loop: SimLoop, index: int) -> None:
        """A UAV move starts: draw whether (and when) the held object drops."""
        self._drop_at = None
        if loop.held is None or self.config.slip <= 0 or not _in_fingers(loop, loop.held):
            return  # nothing in the hand (a dropped object is gone until picked again)
        fires, at = self._slip.random() < self.config.slip, self._slip.uniform(*SLIP_WINDOW_S)
        if fires:
            self._drop_at, self._flight_start, self._step = loop.time + at, loop.time, index
            loop.observers.append(self._watch_flight)

    def _watch_flight(self, loop: SimLoop) -> None:
        if self._drop_at is not None and loop.time >= self._drop_at:
            self._drop(loop)

    def flight_ended(self, loop: SimLoop) -> None:
        """The move ended: a drop still due happens now."""
        if self._drop_at is not None:
            self._drop(loop)
            hold_with_gripper(loop, DROP_S, GRIPPER_OPEN)
        if self._watch_flight in loop.observers:
            loop.observers.remove(self._watch_flight)

    def _drop(self, loop: SimLoop) -> None:
        held, self._drop_at = loop.held, None
        if held is None:
            return
        loop.data.ctrl[loop.model.actuator(GRIPPER_ACTUATOR).id] = GRIPPER_OPEN
        at = max(0.0, loop.time - self._flight_start)
        self.events.append(
            PerturbEvent(kind="slip", step=self._step, object=held, at_s=round(at, 3))
        )

    # ---- bump -------------------------------------------------------------------------
    def before_arm_step(self, loop: SimLoop, index: int, step: ArmStep) -> None:
        """Draw whether ``step``'s object is displaced, and displace it."""
        if self.config.bump <= 0:
            return
        draws = self._bump.random(), self._bump.uniform(*BUMP_RANGE), self._bump.uniform(0, 360)
        if draws[0] >= self.config.bump or not self._bumpable(loop, step.object):
            return
        shift = _displace(loop, step.object, draws[1], draws[2])
        if shift is not None:
            self.events.append(
                PerturbEvent(kind="bump", step=index, object=step.object, shift=shift)
            )

    def _bumpable(self, loop: SimLoop, name: str) -> bool:
        obj = next((o for o in self.episode.objects if o.id == name), None)
        return obj is not None and object_kind(obj.kind).movable and loop.held != name


def _in_fingers(loop: SimLoop, name: str) -> bool:
    """Whether both fingers touch ``name`` (it is in the hand, not dropped)."""
    model = loop.model
    held = set(subtree_geoms(model, model.body(name).id))
    touched = set()
    for finger in (LEFT_FINGER_BODY, RIGHT_FINGER_BODY):
        geoms = set(subtree_geoms(model, model.body(finger).id))
        for i in range(loop.data.ncon):
            g1, g2 = int(loop.data.contact.geom[i][0]), int(loop.data.contact.geom[i][1])
            if (g1 in geoms and g2 in held) or (g2 in geoms and g1 in held):
                touched.add(finger)
                break
    return len(touched) == 2


def _free_qpos(model: mujoco.MjModel, body: str) -> int | None:
    b = model.body(body)
    if int(b.jntnum[0]) != 1:
        return None
    joint = int(b.jntadr[0])
    if model.jnt_type[joint] != mujoco.mjtJoint.mjJNT_FREE:
        return None
    return int(model.jnt_qposadr[joint])


def _below(loop: SimLoop, body: int, point: np.ndarray) -> int:
    """The body hit straight down from ``point`` (-1: nothing), ignoring ``body``."""
    geom = np.zeros(1, dtype=np.int32)
    dist = mujoco.mj_ray(
        loop.model, loop.data, point, np.array([0.0, 0.0, -1.0]), None, 1, body, geom
    )
    if dist < 0 or dist > 2 * _SUPPORT_PROBE or geom[0] < 0:
        return -1
    return int(loop.model.body_rootid[loop.model.geom_bodyid[geom[0]]])


def _footprint(lo: np.ndarray, hi: np.ndarray) -> list[np.ndarray]:
    z = lo[2] + _SUPPORT_PROBE
    return [np.array([x, y, z]) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]


def _riders(loop: SimLoop, name: str, lo: np.ndarray, hi: np.ndarray) -> list[str]:
    """Objects resting on or in ``name`` (their centres over its footprint, above its bottom)."""
    out = []
    for i in range(loop.model.nbody):
        other = loop.model.body(i).name
        if other == name or _free_qpos(loop.model, other) is None or other == loop.held:
            continue
        c = loop.data.xipos[i]
        if lo[0] < c[0] < hi[0] and lo[1] < c[1] < hi[1] and lo[2] < c[2] < hi[2] + 0.2:
            out.append(other)
    return out


def _move(loop: SimLoop, names: list[str], dx: float, dy: float) -> None:
    for name in names:
        adr = _free_qpos(loop.model, name)
        if adr is not None:
            loop.data.qpos[adr] += dx
            loop.data.qpos[adr + 1] += dy
            dof = int(loop.model.jnt_dofadr[loop.model.body(name).jntadr[0]])
            loop.data.qvel[dof : dof + 6] = 0.0
    mujoco.mj_forward(loop.model, loop.data)


def _clear(loop: SimLoop, names: list[str], support: int) -> bool:
    """No moved geom penetrates another body than what it rests on."""
    moved: set[int] = set()
    for name in names:
        moved.update(subtree_geoms(loop.model, loop.model.body(name).id))
    bodies = {loop.model.body(n).id for n in names}
    for i in range(loop.data.ncon):
        c = loop.data.contact[i]
        g1, g2 = int(c.geom[0]), int(c.geom[1])
        if (g1 in moved) == (g2 in moved):
            continue
        other = g2 if g1 in moved else g1
        root = int(loop.model.body_rootid[loop.model.geom_bodyid[other]])
        if root in bodies or root == support:
            continue
        if c.dist < -_CLEARANCE or root != 0:
            return False
    return True


def _displace(
    loop: SimLoop, name: str, distance: float, angle_deg: float
) -> tuple[float, float] | None:
    """Displace ``name`` by ``distance`` in the first direction from ``angle_deg`` (every 45
    degrees) that keeps it on its support and clear; the shift, or None (left in place)."""
    if _free_qpos(loop.model, name) is None:
        return None
    body = loop.model.body(name).id
    lo, hi = object_bounds(loop.model, loop.data, name, solid_only=True)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2] + _SUPPORT_PROBE])
    support = _below(loop, body, centre)
    if support < 0:
        return None
    group = [name, *_riders(loop, name, lo, hi)]
    for k in range(8):
        a = math.radians(angle_deg + 45.0 * k)
        dx, dy = distance * math.cos(a), distance * math.sin(a)
        _move(loop, group, dx, dy)
        shifted = [p + np.array([dx, dy, 0.0]) for p in _footprint(lo, hi)]
        if all(_below(loop, body, p) == support for p in shifted) and _clear(loop, group, support):
            return round(dx, 4), round(dy, 4)
        _move(loop, group, -dx, -dy)
    return None
