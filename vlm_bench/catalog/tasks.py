"""Task specs (``ground_truth/tasks/<suite>/<NN>_<id>.json``), validated and cross-checked."""

from __future__ import annotations

import re
from collections import Counter
from functools import cache
from pathlib import Path

from vlm_bench.catalog.files import load_model
from vlm_bench.catalog.skills import skills
from vlm_bench.catalog.world_catalog import environments, object_kinds, world
from vlm_bench.errors import DataFileError, UnknownNameError
from vlm_bench.resources import ground_truth_dir
from vlm_bench.types.task import Suite, TaskSpec

_FILE = re.compile(r"^(\d+)_([a-z][a-z0-9_]*)\.json$")


def tasks_dir() -> Path:
    """Folder holding one sub-folder of task files per suite."""
    return ground_truth_dir() / "tasks"


def _check(path: Path, task: TaskSpec) -> None:
    """Cross-reference checks a schema cannot express; errors name file and field."""

    def fail(field: str, msg: str) -> None:
        raise DataFileError(str(path), f"{field}: {msg}")

    def unknown(field: str, what: str, name: str, valid: object) -> None:
        fail(field, str(UnknownNameError(what, name, valid)))  # type: ignore[arg-type]

    kinds, colors, skill_table = object_kinds(), world().colors, skills()
    if task.environment not in environments():
        unknown("environment", "environment", task.environment, environments())
    ids: list[str] = []
    for i, obj in enumerate(task.objects):
        if obj.kind not in kinds:
            unknown(f"objects[{i}].kind", "object kind", obj.kind, kinds)
        if obj.color is not None and obj.color not in colors:
            unknown(f"objects[{i}].color", "colour", obj.color, colors)
        ids.append(obj.id)
        ids.extend(p.name for p in kinds[obj.kind].parts)
    dup = [n for n, c in Counter(ids).items() if c > 1]
    if dup:
        fail("objects", f"duplicate object id {dup[0]!r}")
    for i, obj in enumerate(task.objects):
        if obj.on != "floor" and obj.on not in ids:
            unknown(f"objects[{i}].on", "object", obj.on, ["floor", *ids])
    twins = Counter((o.kind, o.color or kinds[o.kind].default_color) for o in task.objects)
    for i, obj in enumerate(task.objects):
        key = (obj.kind, obj.color or kinds[obj.kind].default_color)
        if twins[key] > 1 and not re.search(r"_\d+$", obj.id):
            fail(
                f"objects[{i}].id",
                f"{obj.id!r} shares kind and colour with another object; "
                "number it (e.g. red_cup_1)",
            )
    for i, step in enumerate(task.arm_steps):
        if step.skill not in skill_table or skill_table[step.skill].agent != "ARM":
            arm = [s for s, v in skill_table.items() if v.agent == "ARM"]
            unknown(f"arm_steps[{i}].skill", "ARM skill", step.skill, arm)
        for field in ("object", "target"):
            ref = getattr(step, field)
            if ref is not None and ref not in ids:
                unknown(f"arm_steps[{i}].{field}", "object", ref, ids)
    for i, goal in enumerate(task.goals):
        for field in ("object", "target"):
            ref = getattr(goal, field)
            if ref is not None and ref not in ids:
                unknown(f"goals[{i}].{field}", "object", ref, ids)


def _task_files() -> list[Path]:
    files: list[Path] = []
    for suite in Suite:
        folder = tasks_dir() / suite.value
        files.extend(sorted(p for p in folder.glob("*.json")))
    return files


@cache
def all_tasks() -> tuple[TaskSpec, ...]:
    """Every task, ordered by suite (paper order) then file number (cached)."""
    out: list[TaskSpec] = []
    for path in _task_files():
        match = _FILE.match(path.name)
        if match is None:
            raise DataFileError(str(path), "file name must be NN_<task_id>.json")
        task = load_model(path, TaskSpec)
        if task.id != match.group(2):
            raise DataFileError(str(path), f"id: {task.id!r} differs from the file name")
        if task.suite.value != path.parent.name:
            raise DataFileError(str(path), f"suite: {task.suite.value!r} differs from its folder")
        _check(path, task)
        out.append(task)
    seen = Counter(t.id for t in out)
    dup = [n for n, c in seen.items() if c > 1]
    if dup:
        raise DataFileError(str(tasks_dir()), f"duplicate task id {dup[0]!r}")
    return tuple(out)


def task_index(task_id: str) -> int:
    """Position of a task in the benchmark order (stable, used to spread seeds)."""
    for i, task in enumerate(all_tasks()):
        if task.id == task_id:
            return i
    raise UnknownNameError("task", task_id, [t.id for t in all_tasks()])


def get_task(task_id: str) -> TaskSpec:
    """One task by id; raises listing the valid ids."""
    return all_tasks()[task_index(task_id)]


def tasks_in(suite: Suite | None = None) -> list[TaskSpec]:
    """Tasks of one suite, or all."""
    return [t for t in all_tasks() if suite is None or t.suite == suite]
