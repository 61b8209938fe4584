"""The 60 task files: counts, references, instruction rules and layout geometry.

What a task holds: docs/design.md#tasks.
"""

from __future__ import annotations

import math
import re
from collections import Counter

import pytest

from vlm_bench.catalog.tasks import all_tasks, tasks_in
from vlm_bench.catalog.world_catalog import environments, object_kind
from vlm_bench.types.task import PlacedObject, Suite, TaskSpec

SUITE_COUNTS = {
    Suite.BASE: 20,
    Suite.OBJECT_SPATIAL: 15,
    Suite.SEMANTIC: 15,
    Suite.LONG_HORIZON: 10,
}
MIN_TASKS_PER_ENVIRONMENT = 6
CLOSE = 0.25  # m: consecutive ARM-step objects at most this far apart need no UAV move ...
FAR = 1.2  # m: ... or at least this far apart, so the GT move is never borderline
MIN_GAP = 0.04  # m between bounding boxes of objects on the same support
TABLE_MARGIN = 0.08  # m from a table's edge
FLOOR_GAP = 0.3  # m between pieces of furniture on the floor
CABINET_FRONT_CLEAR = 1.2  # m in front of a drawer cabinet kept free of tables

# The phenomenon each Semantic Understanding task is named after must appear in its implicit
# instruction (whole words, case-insensitive).
SEMANTIC_PHRASES: dict[str, tuple[str, ...]] = {
    "synonym_container": ("container",),
    "synonym_block_bin": ("block", "bin"),
    "verb_drop": ("drop",),
    "synonym_cup_dish": ("cup", "dish"),
    "preposition_onto": ("onto",),
    "material_tin": ("tin",),
    "function_detergent": ("detergent",),
    "synonym_center": ("center",),
    "attribute_metal": ("metal",),
    "superlative_highest": ("highest",),
    "negation_constraint": ("not the brown one",),
    "contextual_spare_part": ("spare part",),
    "jargon_vision_sensor": ("vision sensor",),
    "preposition_by_dont": ("by the", "don't put"),
    "abstract_intent_clear": ("clear the desk",),
}
UAV_WORDS = re.compile(
    r"\b(fly|flight|hover|ascend|descend|drone|uav|frontleft|frontright|backleft|backright)\b",
    re.IGNORECASE,
)

TASKS = all_tasks()
TASK_IDS = [t.id for t in TASKS]


def _by_id(task: TaskSpec) -> dict[str, PlacedObject]:
    return {o.id: o for o in task.objects}


def _owner(task: TaskSpec, ref: str) -> PlacedObject:
    """The object itself, or the cabinet/stove that owns a part (drawer, knob)."""
    for obj in task.objects:
        if obj.id == ref or any(p.name == ref for p in object_kind(obj.kind).parts):
            return obj
    raise KeyError(ref)


def _half_extents(obj: PlacedObject) -> tuple[float, float]:
    """Half sizes of the object's axis-aligned bounding box in the world."""
    sx, sy, _ = object_kind(obj.kind).size
    c, s = abs(math.cos(math.radians(obj.yaw_deg))), abs(math.sin(math.radians(obj.yaw_deg)))
    return (c * sx + s * sy) / 2, (s * sx + c * sy) / 2


def _box_gap(a: PlacedObject, b: PlacedObject) -> float:
    """Clearance between two bounding boxes (negative when they overlap)."""
    ax, ay = _half_extents(a)
    bx, by = _half_extents(b)
    return max(abs(a.xy[0] - b.xy[0]) - ax - bx, abs(a.xy[1] - b.xy[1]) - ay - by)


def _anchors(
    task: TaskSpec, ref: str, moved: dict[str, tuple[float, float]]
) -> list[tuple[float, float]]:
    """Points a step's object is judged from: its (tracked) centre; for a part, also its handle."""
    owner = _owner(task, ref)
    if owner.id != ref:
        part = next(p for p in object_kind(owner.kind).parts if p.name == ref)
        yaw = math.radians(owner.yaw_deg)
        hx, hy = part.handle[0], part.handle[1]
        handle = (
            owner.xy[0] + math.cos(yaw) * hx - math.sin(yaw) * hy,
            owner.xy[1] + math.sin(yaw) * hx + math.cos(yaw) * hy,
        )
        return [tuple(owner.xy), handle]
    return [moved.get(ref, tuple(owner.xy))]


def test_sixty_tasks_in_four_suites() -> None:
    assert len(TASKS) == 60
    for suite, count in SUITE_COUNTS.items():
        assert len(tasks_in(suite)) == count, suite


def test_ids_unique() -> None:
    assert len(set(TASK_IDS)) == len(TASK_IDS)
    names = [t.name for t in TASKS]
    assert len(set(names)) == len(names)


def test_every_environment_used() -> None:
    counts = Counter(t.environment for t in TASKS)
    for env in environments():
        assert counts[env] >= MIN_TASKS_PER_ENVIRONMENT, (env, counts)


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_references_exist(task: TaskSpec) -> None:
    ids = set(_by_id(task))
    for obj in task.objects:
        ids.update(p.name for p in object_kind(obj.kind).parts)
    for step in task.arm_steps:
        assert step.object in ids, (task.id, step)
        assert step.target is None or step.target in ids, (task.id, step)
    for goal in task.goals:
        assert goal.object in ids, (task.id, goal)
        assert goal.target is None or goal.target in ids, (task.id, goal)
    for obj in task.objects:
        assert obj.color is not None, (task.id, obj.id)
        assert obj.on == "floor" or obj.on in ids, (task.id, obj.id)


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_instructions(task: TaskSpec) -> None:
    explicit, implicit = task.instructions.explicit, task.instructions.implicit
    assert explicit.strip().lower() != implicit.strip().lower()
    for text in (explicit, implicit):
        assert not UAV_WORDS.search(text), (task.id, text)
        assert text.strip()[-1] in ".?!", (task.id, text)


def test_semantic_phrases() -> None:
    semantic = {t.id: t for t in tasks_in(Suite.SEMANTIC)}
    assert set(semantic) == set(SEMANTIC_PHRASES)
    for task_id, phrases in SEMANTIC_PHRASES.items():
        text = semantic[task_id].instructions.implicit.lower()
        for phrase in phrases:
            assert re.search(rf"\b{re.escape(phrase)}\b", text), (task_id, phrase, text)


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_consecutive_steps_close_or_far(task: TaskSpec) -> None:
    """No GT move is borderline: consecutive ARM objects are clearly in reach or clearly not.

    Checked from the task-file positions and from positions tracked through the plan (a placed
    object sits at its destination; a pushed object ends at its push target).
    """
    moved: dict[str, tuple[float, float]] = {}
    held: str | None = None
    prev: str | None = None
    for step in task.arm_steps:
        if prev is not None:
            for tracked in (moved, {}):
                first, second = _anchors(task, prev, tracked), _anchors(task, step.object, tracked)
                # Two parts: owner with owner, handle with handle; else every combination.
                pairs = (
                    zip(first, second, strict=True)
                    if len(first) == len(second) == 2
                    else ((a, b) for a in first for b in second)
                )
                for a, b in pairs:
                    d = math.dist(a, b)
                    assert d <= CLOSE or d >= FAR, (task.id, prev, step.object, round(d, 3))
        if step.skill == "pick":
            held = step.object
        elif step.skill == "place" and held is not None:
            moved[held] = _anchors(task, step.object, moved)[-1]
            held = None
        elif step.skill == "push" and step.target is not None:
            moved[step.object] = _anchors(task, step.target, moved)[-1]
        prev = step.object


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_layout(task: TaskSpec) -> None:
    by_id = _by_id(task)
    objects = task.objects
    for i, a in enumerate(objects):
        for b in objects[i + 1 :]:
            if a.on != b.on:
                continue
            gap = FLOOR_GAP if a.on == "floor" else MIN_GAP
            assert _box_gap(a, b) >= gap - 1e-9, (task.id, a.id, b.id, round(_box_gap(a, b), 3))
        if a.on != "floor" and by_id[a.on].kind == "table":
            table = by_id[a.on]
            tx, ty = _half_extents(table)
            ax, ay = _half_extents(a)
            assert abs(a.xy[0] - table.xy[0]) + ax <= tx - TABLE_MARGIN + 1e-9, (task.id, a.id)
            assert abs(a.xy[1] - table.xy[1]) + ay <= ty - TABLE_MARGIN + 1e-9, (task.id, a.id)
        if a.kind in ("table", "drawer_cabinet", "stove"):
            assert a.on == "floor" and a.fixed and a.role in ("support", "fixture"), (task.id, a.id)


def _corners(
    cx: float, cy: float, sx: float, sy: float, yaw_deg: float
) -> list[tuple[float, float]]:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    out = []
    for ux, uy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        x, y = ux * sx / 2, uy * sy / 2
        out.append((cx + c * x - s * y, cy + s * x + c * y))
    return out


def _rects_intersect(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> bool:
    """Separating-axis test of two rectangles given by their corners."""
    for poly in (a, b):
        for i in range(4):
            ex, ey = poly[(i + 1) % 4][0] - poly[i][0], poly[(i + 1) % 4][1] - poly[i][1]
            pa = [-ey * x + ex * y for x, y in a]
            pb = [-ey * x + ex * y for x, y in b]
            if max(pa) <= min(pb) or max(pb) <= min(pa):
                return False
    return True


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_cabinet_front_is_clear(task: TaskSpec) -> None:
    """Nothing on the floor stands within 1.2 m in front of a drawer cabinet."""
    for cab in (o for o in task.objects if o.kind == "drawer_cabinet"):
        depth, width, _ = object_kind(cab.kind).size
        yaw = math.radians(cab.yaw_deg)
        reach = depth / 2 + CABINET_FRONT_CLEAR / 2
        front = _corners(
            cab.xy[0] + math.cos(yaw) * reach,
            cab.xy[1] + math.sin(yaw) * reach,
            CABINET_FRONT_CLEAR,
            width,
            cab.yaw_deg,
        )
        for other in task.objects:
            if other is cab or other.on != "floor":
                continue
            sx, sy, _ = object_kind(other.kind).size
            footprint = _corners(other.xy[0], other.xy[1], sx, sy, other.yaw_deg)
            assert not _rects_intersect(front, footprint), (task.id, other.id)


@pytest.mark.parametrize("task", TASKS, ids=TASK_IDS)
def test_twins_are_numbered_and_roles_sane(task: TaskSpec) -> None:
    keys = Counter((o.kind, o.color) for o in task.objects)
    for obj in task.objects:
        if keys[(obj.kind, obj.color)] > 1:
            assert re.search(r"_\d+$", obj.id), (task.id, obj.id)
    step_objects = {s.object for s in task.arm_steps}
    for obj in task.objects:
        if obj.role == "distractor":
            assert obj.id not in step_objects, (task.id, obj.id)
        if obj.role == "target":
            assert obj.id in step_objects, (task.id, obj.id)
