"""Where a perturbation puts things: whether an object is in the fingers, and displacing an
object (and what rests on it) on its support, clear of the others."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import LEFT_FINGER_BODY, RIGHT_FINGER_BODY
from vlm_bench.sim.objects.bounds import object_bounds, subtree_geoms

_SUPPORT_PROBE = 0.02  # m below an object's bottom: what it rests on is hit within this
_CLEARANCE = 0.005  # m: a displaced object may not come closer than this to another


def in_fingers(loop: SimLoop, name: str) -> bool:
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


def displace(
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
