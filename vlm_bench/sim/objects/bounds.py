"""Exact world-frame bounding boxes of compiled geoms and objects (for tests and placement)."""

from __future__ import annotations

import mujoco
import numpy as np

from vlm_bench.errors import UnknownNameError
from vlm_bench.types.base import FloatArray as Vec

_GEOM = mujoco.mjtGeom


def geom_bounds(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> tuple[Vec, Vec]:
    """World-frame (min, max) corners of one geom, exact for primitives and meshes.

    Args:
        model: Compiled model.
        data: Data after ``mj_kinematics`` (or ``mj_forward``).
        geom: Geom id; planes and height fields are not supported.

    Returns:
        The lower and upper corners of the axis-aligned box that holds the geom.
    """
    centre = np.asarray(data.geom_xpos[geom], dtype=np.float64)
    rot = np.asarray(data.geom_xmat[geom], dtype=np.float64).reshape(3, 3)
    size = np.asarray(model.geom_size[geom], dtype=np.float64)
    gtype = int(model.geom_type[geom])
    if gtype == _GEOM.mjGEOM_SPHERE:
        half = np.full(3, size[0])
    elif gtype == _GEOM.mjGEOM_CAPSULE:
        half = np.abs(rot[:, 2]) * size[1] + size[0]
    elif gtype == _GEOM.mjGEOM_CYLINDER:
        axis = rot[:, 2]
        half = np.abs(axis) * size[1] + size[0] * np.sqrt(np.clip(1.0 - axis**2, 0.0, 1.0))
    elif gtype == _GEOM.mjGEOM_BOX:
        half = np.abs(rot) @ size
    elif gtype == _GEOM.mjGEOM_ELLIPSOID:
        half = np.sqrt((rot * size) ** 2 @ np.ones(3))
    elif gtype == _GEOM.mjGEOM_MESH:
        mesh = int(model.geom_dataid[geom])
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        verts = np.asarray(model.mesh_vert[start : start + count], dtype=np.float64)
        world = verts @ rot.T + centre
        return world.min(axis=0), world.max(axis=0)
    else:
        raise ValueError(f"geom {geom} has unsupported type {gtype} for bounds")
    return centre - half, centre + half


def subtree_geoms(model: mujoco.MjModel, body: int | str, solid_only: bool = False) -> list[int]:
    """Ids of the geoms on ``body`` (an id or a name) and on every body below it (an object with
    its parts), ascending; with ``solid_only``, only the colliding ones."""
    root = model.body(body).id
    inside = np.zeros(model.nbody, dtype=bool)
    for b in range(model.nbody):  # parents come before children in a compiled model
        inside[b] = b == root or (b > 0 and inside[model.body_parentid[b]])
    keep = inside[model.geom_bodyid]
    if solid_only:
        keep &= (model.geom_contype != 0) | (model.geom_conaffinity != 0)
    return [int(g) for g in np.flatnonzero(keep)]


def object_bounds(
    model: mujoco.MjModel, data: mujoco.MjData, name: str, solid_only: bool = False
) -> tuple[Vec, Vec]:
    """World-frame (min, max) corners of an object: its body and all its parts.

    Args:
        model: Compiled model.
        data: Data after ``mj_kinematics`` (or ``mj_forward``).
        name: Object id (= body name).
        solid_only: Skip decoration geoms that never collide.

    Returns:
        The lower and upper corners of the world axis-aligned box around the object.
    """
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    if body < 0:
        names = (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(model.nbody))
        raise UnknownNameError("body", name, [n for n in names if n])
    boxes = [geom_bounds(model, data, g) for g in subtree_geoms(model, body, solid_only)]
    lows = np.array([lo for lo, _ in boxes])
    highs = np.array([hi for _, hi in boxes])
    return lows.min(axis=0), highs.max(axis=0)
