"""Where a held object is let go: the release point in or on a destination, and whether it
may be dropped in from above the rim instead."""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.rules.work import CONTAINER_FLOOR
from vlm_bench.sim.constants import TCP_SITE, part_joint
from vlm_bench.sim.objects.bounds import geom_bounds, object_bounds
from vlm_bench.types.base import FloatArray
from vlm_bench.types.episode import Episode
from vlm_bench.types.world import ObjectKind

HAND_HALF = 0.105  # m: half the Panda hand's length, along its fingers' closing axis
DRAWER_DROP_SIZE = 0.1  # m: the widest object dropped into a drawer from above its front


def kind_of(episode: Episode, obj: str) -> ObjectKind | None:
    """The catalogue kind of the episode's object ``obj`` (``None``: not an object, a part)."""
    return next((object_kind(o.kind) for o in episode.objects if o.id == obj), None)


def is_vessel(kind: ObjectKind | None) -> bool:
    """Whether objects go inside ``kind`` (a basket, a bowl), rather than on it (a plate) or
    into a part (``None``: a drawer)."""
    return kind is not None and kind.container and not kind.support


def hang(hand: Hand, held: str) -> float:
    """TCP height above the held object's bottom (m)."""
    loop = hand.loop
    lo, _ = object_bounds(loop.model, loop.data, held, solid_only=True)
    return float(loop.data.site(TCP_SITE).xpos[2] - lo[2])


def top_of(hand: Hand, dest: str) -> float:
    """Top of the destination (m)."""
    _, hi = object_bounds(hand.loop.model, hand.loop.data, dest, solid_only=True)
    return float(hi[2])


def can_drop_into(hand: Hand, episode: Episode, held: str, dest: str) -> bool:
    """Whether ``held`` may be dropped into ``dest`` from above its rim: ``dest`` holds things
    inside it (a basket, a bowl, an open drawer's box for objects at most
    :data:`DRAWER_DROP_SIZE` across, as a longer one can land across a wall after the fall
    from above the front; not a plate) and is deeper than the object is tall (a taller one
    topples out over the rim)."""
    model, data = hand.loop.model, hand.loop.data
    kind = kind_of(episode, dest)
    hlo, hhi = object_bounds(model, data, held, solid_only=True)
    if is_vessel(kind):
        lo, hi = object_bounds(model, data, dest, solid_only=True)
        depth = float(hi[2] - lo[2]) - CONTAINER_FLOOR
    elif kind is None and any(p.id == dest and p.kind == "drawer" for p in episode.parts):
        _, wall = geom_bounds(model, data, model.geom(f"{dest}/box_front").id)
        depth = float(wall[2]) - float(data.body(dest).xpos[2])  # the floor: body origin
        if float(np.max(hhi[:2] - hlo[:2])) > DRAWER_DROP_SIZE:
            return False
    else:
        return False
    return float(hhi[2] - hlo[2]) < depth


def release_point(hand: Hand, episode: Episode, held: str, dest: str) -> FloatArray:
    """TCP position that sets the held object down 2 cm above its resting place."""
    loop = hand.loop
    lo, hi = object_bounds(loop.model, loop.data, dest, solid_only=True)
    kind = kind_of(episode, dest)
    if is_vessel(kind):
        rest = float(lo[2]) + CONTAINER_FLOOR
    elif kind is None:  # a drawer: its floor is the body origin's height
        rest = float(loop.data.body(dest).xpos[2])
        lo, hi = _exposed(hand, episode, dest, lo, hi)
    else:
        rest = float(hi[2])
    x, y = _beside_contents(hand, episode, dest, held, lo, hi)
    return np.array([x, y, rest + hang(hand, held) + 0.02])


def _exposed(
    hand: Hand, episode: Episode, drawer: str, lo: FloatArray, hi: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The part of an open drawer's bounds [lo, hi] out in front of its cabinet: from the
    front panel's inner face back by the opening (the rest lies under the cabinet's top, where
    no hand reaches down). The cabinet faces along a world axis (fixed furniture is set
    square)."""
    model, data = hand.loop.model, hand.loop.data
    parent = next(p.parent for p in episode.parts if p.id == drawer)
    axis = hand.outward_axis(parent)
    k = int(np.argmax(np.abs(axis[:2])))
    sign = math.copysign(1.0, float(axis[k]))
    flo, fhi = geom_bounds(model, data, model.geom(f"{drawer}/front").id)
    inner = float(flo[k] if sign > 0 else fhi[k])
    opening = float(data.qpos[model.joint(part_joint(drawer)).qposadr[0]])
    a, b = sorted((inner, inner - sign * opening))
    lo, hi = lo.copy(), hi.copy()
    lo[k], hi[k] = max(float(lo[k]), a), min(float(hi[k]), b)
    return lo, hi


def _contents(
    hand: Hand, episode: Episode, dest: str, held: str, lo: FloatArray, hi: FloatArray
) -> list[tuple[FloatArray, float]]:
    """What already lies in the destination spanning [lo, hi]: each object's horizontal
    centre and half its widest side."""
    model, data = hand.loop.model, hand.loop.data
    boxes = []
    for o in episode.objects:
        if o.id in (dest, held):
            continue
        olo, ohi = object_bounds(model, data, o.id, solid_only=True)
        mid = (olo + ohi) / 2
        within = np.all(lo[:2] <= mid[:2]) and np.all(mid[:2] <= hi[:2])
        if within and lo[2] - 0.01 <= olo[2] < hi[2]:  # in it, not what it stands on
            boxes.append((mid[:2], float(np.max(ohi[:2] - olo[:2])) / 2))
    return boxes


def _beside_contents(
    hand: Hand, episode: Episode, dest: str, held: str, lo: FloatArray, hi: FloatArray
) -> tuple[float, float]:
    """Release x, y in the destination spanning [lo, hi]: its centre, or off what already lies
    there (a second object into the same basket): of a grid of points keeping the held object
    inside, the nearest to the centre where it clears the contents' boxes, else the one
    farthest from them (walls are for the hand's planning to clear)."""
    boxes = _contents(hand, episode, dest, held, lo, hi)
    centre = (lo[:2] + hi[:2]) / 2
    if not boxes:
        return float(centre[0]), float(centre[1])
    hlo, hhi = object_bounds(hand.loop.model, hand.loop.data, held, solid_only=True)
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
