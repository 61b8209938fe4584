"""Object layouts: canonical positions at seed 0, jittered poses for other seeds."""

from __future__ import annotations

from collections import Counter

import numpy as np

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes.plane_geometry import rect_corners, rects_overlap
from vlm_bench.rules import rotate_xy
from vlm_bench.rules.work import rest_height
from vlm_bench.types.base import Vec3
from vlm_bench.types.episode import EpisodeObject, PartRef
from vlm_bench.types.task import PlacedObject, TaskSpec

POS_JITTER = 0.03  # m, per axis, movable objects
YAW_JITTER = 20.0  # deg
EDGE_MARGIN = 0.02  # m, objects stay this far inside their support's top
MIN_GAP = 0.01  # m between bounding boxes on the same support
GRIPPER_SPAN = 0.075  # m: widest an object may be for the open gripper to close around it
HAND_CLEARANCE = 0.08  # m: from a long object to a taller neighbour, for the closing hand
PALM_CLEARANCE = 0.03  # m: from an object the open hand fits around to a taller neighbour
RIM_GRASPED = frozenset({"bowl", "mug"})  # held by the rim, from whichever side is free
TABLE_KINDS = ("low_table", "table", "high_table")
"""Height variants of a task file's ``table`` (tops 0.40, 0.75, 1.10 m in the catalogue), one
drawn per table per layout at seeds 1-9. Their tops lie 0.35 m apart: working altitudes differ
by the vertical threshold (0.20 m) plus more than its margin (0.10 m) either way."""


def _support_top(support: EpisodeObject) -> float:
    kind = object_kind(support.kind)
    return rest_height(support.pos[2], kind.size[2], container=kind.container, support=kind.support)


def _ordered(objects: tuple[PlacedObject, ...]) -> list[PlacedObject]:
    """Supports before what rests on them."""
    done: set[str] = {"floor"}
    out: list[PlacedObject] = []
    pending = list(objects)
    while pending:
        ready = [o for o in pending if o.on in done or o.on not in {p.id for p in objects}]
        if not ready:  # a cycle: the catalogue validation prevents it; place the rest as listed
            ready = pending
        for obj in ready:
            out.append(obj)
            done.add(obj.id)
            pending.remove(obj)
    return out


def set_of_marks_labels(objects: tuple[PlacedObject, ...]) -> dict[str, str]:
    """Ids to draw as labels: objects that share kind and colour with another object."""

    def key(o: PlacedObject) -> tuple[str, str | None]:
        return o.kind, o.color or object_kind(o.kind).default_color

    counts = Counter(key(o) for o in objects)
    return {o.id: o.id for o in objects if counts[key(o)] > 1}


def support_kinds(task: TaskSpec, rng: np.random.Generator | None) -> dict[str, str]:
    """Kind of each ``table`` in ``task``: one of :data:`TABLE_KINDS` drawn independently per
    table, or the task file's ``table`` with ``rng=None`` (the canonical layout)."""
    tables = [o.id for o in task.objects if o.kind == "table"]
    if rng is None:
        return {t: "table" for t in tables}
    return {t: TABLE_KINDS[int(rng.integers(len(TABLE_KINDS)))] for t in tables}


def place_objects(
    task: TaskSpec, rng: np.random.Generator | None, kinds: dict[str, str] | None = None
) -> list[EpisodeObject]:
    """Poses of every object; ``rng=None`` gives the canonical (seed 0) layout. ``kinds`` maps
    an object id to the kind it is built as (a table's height variant); others keep the task's.

    Raises ``ValueError`` when a jittered layout overlaps or leaves a support (callers resample).
    """
    labels = set_of_marks_labels(task.objects)
    placed: dict[str, EpisodeObject] = {}
    shift: dict[str, tuple[float, float]] = {"floor": (0.0, 0.0)}
    for spec in _ordered(task.objects):
        kind = object_kind((kinds or {}).get(spec.id, spec.kind))
        jx = jy = dyaw = 0.0
        if rng is not None and not spec.fixed and kind.movable:
            jx, jy = rng.uniform(-POS_JITTER, POS_JITTER, size=2)
            dyaw = float(rng.uniform(-YAW_JITTER, YAW_JITTER))
        base = shift.get(spec.on, (0.0, 0.0))
        x, y = spec.xy[0] + base[0] + jx, spec.xy[1] + base[1] + jy
        shift[spec.id] = (base[0] + jx, base[1] + jy)
        z = 0.0 if spec.on == "floor" else _support_top(placed[spec.on])
        placed[spec.id] = EpisodeObject(
            id=spec.id,
            kind=kind.name,
            color=spec.color or kind.default_color or "gray",
            pos=(round(x, 4), round(y, 4), round(z, 4)),
            yaw_deg=round(spec.yaw_deg + dyaw, 2),
            on=spec.on,
            role=spec.role,
            initial=dict(spec.initial),
            label=labels.get(spec.id),
        )
    objects = [placed[o.id] for o in task.objects]
    check_layout(objects)
    return objects


def footprint(obj: EpisodeObject) -> np.ndarray:
    """Corners of the object's footprint."""
    return rect_corners(obj.pos, object_kind(obj.kind).size[:2], obj.yaw_deg)


def check_layout(objects: list[EpisodeObject]) -> None:
    by_id = {o.id: o for o in objects}
    for i, a in enumerate(objects):
        if a.on != "floor":
            sup = by_id[a.on]
            sup_size = object_kind(sup.kind).size
            inner = rect_corners(
                sup.pos, (sup_size[0] - 2 * EDGE_MARGIN, sup_size[1] - 2 * EDGE_MARGIN), sup.yaw_deg
            )
            if not _inside(footprint(a), inner):
                raise ValueError(f"{a.id} is not inside the top of {sup.id}")
        for b in objects[i + 1 :]:
            if a.on == b.on and rects_overlap(footprint(a), footprint(b), _gap(a, b)):
                raise ValueError(f"{a.id} overlaps {b.id}")


def _hand_room(obj: EpisodeObject, neighbour: EpisodeObject) -> float:
    """Room (m) a top-down hand needs beside ``obj`` on the side of a taller ``neighbour``.

    The Panda hand is 0.2 m long along its fingers' closing axis and 6 cm thick across it.
    A long object must be closed on across its narrow side, so the hand's length points at a
    neighbour lying across that side: :data:`HAND_CLEARANCE`. Beside its length, or beside an
    object that fits the open hand (the hand turns its thickness to the neighbour, to grasp or
    to push it): :data:`PALM_CLEARANCE`. Rim-held bowls and mugs are held from a free side.
    """
    kind, other = object_kind(obj.kind), object_kind(neighbour.kind)
    if not kind.graspable or not kind.movable or kind.name in RIM_GRASPED:
        return 0.0
    if other.size[2] <= kind.size[2]:
        return 0.0
    if max(kind.size[:2]) <= GRIPPER_SPAN:
        return PALM_CLEARANCE
    dx, dy = neighbour.pos[0] - obj.pos[0], neighbour.pos[1] - obj.pos[1]
    lx, ly = rotate_xy(dx, dy, -obj.yaw_deg)  # the neighbour in the object's frame
    across, along = (abs(lx), abs(ly)) if kind.size[0] < kind.size[1] else (abs(ly), abs(lx))
    return HAND_CLEARANCE if across > along else PALM_CLEARANCE


def _gap(a: EpisodeObject, b: EpisodeObject) -> float:
    """Least gap (m) between the footprints of two objects on the same support."""
    return max(MIN_GAP, _hand_room(a, b), _hand_room(b, a))


def _inside(corners: np.ndarray, outer: np.ndarray) -> bool:
    center = outer.mean(axis=0)
    ex, ey = outer[0] - outer[1], outer[1] - outer[2]
    lx, ly = float(np.linalg.norm(ex)), float(np.linalg.norm(ey))
    for p in corners:
        d = p - center
        if abs(float(d @ ex) / lx) > lx / 2 + 1e-9 or abs(float(d @ ey) / ly) > ly / 2 + 1e-9:
            return False
    return True


def part_refs(objects: list[EpisodeObject]) -> list[PartRef]:
    """World positions of every articulated part's handle at the episode start."""
    out: list[PartRef] = []
    for obj in objects:
        for part in object_kind(obj.kind).parts:
            hx, hy, hz = part.handle
            if part.kind == "drawer":
                hx += obj.initial.get(part.name, 0.0)
            out.append(
                PartRef(
                    id=part.name, parent=obj.id, kind=part.kind, handle=_world(obj, (hx, hy, hz))
                )
            )
    return out


def _world(obj: EpisodeObject, local: Vec3) -> Vec3:
    dx, dy = rotate_xy(local[0], local[1], obj.yaw_deg)
    return (round(obj.pos[0] + dx, 4), round(obj.pos[1] + dy, 4), round(obj.pos[2] + local[2], 4))
