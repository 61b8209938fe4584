"""Which contacts a collision check reports: the collision masks that leave world pairs out of
``mj_collision`` and the filter that turns a check's contacts into its hits."""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

WORLD = (2, 1)
"""(contype, conaffinity) of a world geom in a collision-check model: no world pair collides."""
ROBOT = (1, 3)
"""(contype, conaffinity) of a robot geom there: it collides with the world and itself."""
HELD = (0, 2)
"""(contype, conaffinity) of a held object's geom there: it collides with the world only. Its
contacts with the fingers holding it (two in three of a check's contacts while one is held)
would never be hits (:func:`contact_hits`), so they are not made."""


def robot_only_collisions(model: mujoco.MjModel, robot: NDArray[np.bool_]) -> bool:
    """Give ``model``'s colliding geoms the masks :data:`WORLD` and :data:`ROBOT` (``robot``:
    per-geom flags), so ``mj_collision`` reports only pairs with a robot geom in them: objects
    resting on tables (~35 contacts per check) are never reported. Exact where every geom
    either collides with all others or with none (contype = conaffinity ∈ {0, 1}, as in all
    the benchmark's scenes); other masks are left as they are. Whether it set them."""
    types, affinities = model.geom_contype, model.geom_conaffinity
    if not np.all((types == affinities) & (types <= 1)):
        return False
    robot_side(model, np.flatnonzero(robot))
    world = np.flatnonzero(~robot & ((types | affinities) != 0))
    model.geom_contype[world], model.geom_conaffinity[world] = WORLD
    return True


def robot_side(
    model: mujoco.MjModel, geoms: NDArray[np.int64], masks: tuple[int, int] = ROBOT
) -> None:
    """Give ``geoms`` (colliding ones) the collision ``masks`` of the robot's side: the robot's
    own (:data:`ROBOT`) or a held object's (:data:`HELD`)."""
    solid = geoms[(model.geom_contype[geoms] | model.geom_conaffinity[geoms]) != 0]
    model.geom_contype[solid], model.geom_conaffinity[solid] = masks


def contact_hits(
    s: mujoco.MjData,
    clearance: float,
    own: list[bool],
    robot: list[bool],
    ignore: list[bool] | None,
) -> tuple[int, ...]:
    """The hits of :meth:`CollisionChecker.collisions` in ``s``'s contacts, in contact order:
    for each contact within ``clearance`` of an ``own`` geom (the robot's or the held object's)
    with a geom that is neither that nor in ``ignore``, that geom; for each penetrating contact
    of two ``robot`` geoms, the first (per-geom flags). A plain loop: a check has a handful of
    contacts, where numpy's per-call cost is most of the time."""
    if s.ncon == 0:
        return ()
    contact = s.contact
    hits = []
    for (g0, g1), dist in zip(contact.geom.tolist(), contact.dist.tolist(), strict=True):
        if not dist <= clearance:
            continue
        if robot[g0] and robot[g1] and dist <= 0.0:
            hits.append(g0)
        elif own[g0] != own[g1]:
            other = g1 if own[g0] else g0
            if ignore is None or not ignore[other]:
                hits.append(other)
    return tuple(hits)
