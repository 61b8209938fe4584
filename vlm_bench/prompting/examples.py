"""Few-shot example scenes: loading, their scene text and derived plans, seeded selection and
the leakage check.

An example is data: objects placed relative to the UAV and the ARM steps its instruction asks
for. Its scene text is written by the same :func:`~vlm_bench.rules.format_scene` as
``--scene-as-text``, and its UAV moves are derived by the prompt's rules
(:func:`~vlm_bench.rules.plan_from_scene`, the GT builder's own :func:`approach_moves`), so no
example can teach a rule the ground truth does not follow.
"""

from __future__ import annotations

import hashlib
import re
from collections import Counter
from collections.abc import Iterable, Sequence
from functools import cache

from pydantic import Field

from vlm_bench.catalog.files import load_model
from vlm_bench.catalog.skills import skills
from vlm_bench.errors import ConfigError, DataFileError
from vlm_bench.resources import prompts_dir
from vlm_bench.rules import (
    DRAWER_FLOOR_BELOW_HANDLE,
    DRAWER_INSIDE_BEHIND_HANDLE,
    SceneEntry,
    format_scene,
    plan_from_scene,
    rule_numbers,
)
from vlm_bench.rules.work import rest_height
from vlm_bench.types.base import Frozen
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.prompt import ExampleObject, FewShotExample, FewShotLibrary
from vlm_bench.types.task import TaskSpec

EXAMPLES_FILE = "few_shot_examples.json"

# Words that carry no task identity; dropped before comparing instructions.
_STOPWORD_TEXT = """
a an the it its it's to of in into on onto and then with by from for at is are be this that
please can could you your me my i i'm we our up down over there here some one
"""
_STOPWORDS = frozenset(_STOPWORD_TEXT.split())


@cache
def few_shot_examples() -> tuple[FewShotExample, ...]:
    """The example scenes of ``prompts/few_shot_examples.json``, validated (cached).

    Raises:
        DataFileError: The file is malformed, an id repeats, or a step names an unknown or
            non-ARM skill.
    """
    path = prompts_dir() / EXAMPLES_FILE
    library = load_model(path, FewShotLibrary)
    table = skills()
    for n, ex in enumerate(library.examples):
        for i, step in enumerate(ex.arm_steps):
            if step.skill not in table or table[step.skill].agent != "ARM":
                arm = sorted(s for s, v in table.items() if v.agent == "ARM")
                raise DataFileError(
                    str(path),
                    f"examples[{n}].arm_steps[{i}].skill: {step.skill!r} is not an ARM skill; "
                    f"valid: {', '.join(arm)}",
                )
    dup = [i for i, c in Counter(ex.id for ex in library.examples).items() if c > 1]
    if dup:
        raise DataFileError(str(path), f"examples: duplicate id {dup[0]!r}")
    return library.examples


def _entry(obj: ExampleObject, uav_height: float) -> SceneEntry:
    """An example object as the scene text describes it (body frame, UAV centre at 0)."""
    if obj.part is None:
        centre = obj.bottom + obj.tall / 2
        rest = rest_height(obj.bottom, obj.tall, container=obj.holds == "in", support=False)
        return SceneEntry(
            id=obj.id,
            kind="object",
            point=(obj.right, obj.forward, round(centre - uav_height, 2)),
            floor_height=round(centre, 2),
            tall=obj.tall,
            rest=(obj.right, obj.forward, round(rest - uav_height, 2)),
        )
    handle = (obj.right, obj.forward, round(obj.bottom - uav_height, 2))
    if obj.part == "knob":
        return SceneEntry(
            id=obj.id, kind="knob", point=handle, floor_height=obj.bottom, owner=obj.part_of
        )
    assert obj.pull is not None  # a drawer has one (ExampleObject checks)
    px, py = obj.pull
    norm = (px * px + py * py) ** 0.5
    pull = (round(px / norm, 3), round(py / norm, 3))
    inside = (
        round(obj.right - pull[0] * DRAWER_INSIDE_BEHIND_HANDLE, 2),
        round(obj.forward - pull[1] * DRAWER_INSIDE_BEHIND_HANDLE, 2),
        round(obj.bottom - DRAWER_FLOOR_BELOW_HANDLE - uav_height, 2),
    )
    return SceneEntry(
        id=obj.id,
        kind="drawer",
        point=handle,
        floor_height=obj.bottom,
        owner=obj.part_of,
        opening=obj.opening,
        pull=pull,
        rest=inside,
        standoff=rule_numbers().drawer_standoff,
    )


def example_entries(example: FewShotExample) -> list[SceneEntry]:
    """The example's objects and parts as scene entries, in file order."""
    return [_entry(obj, example.uav_height) for obj in example.objects]


def example_scene_text(example: FewShotExample) -> str:
    """The example's scene in the words of ``--scene-as-text``."""
    return format_scene(example_entries(example), example.uav_height)


def example_plan(example: FewShotExample) -> list[UavStep | ArmStep]:
    """The example's plan: its ARM steps with the UAV moves the prompt's rules give."""
    return plan_from_scene(example_entries(example), example.arm_steps)


def _rank(seed: int, key: str, example_id: str) -> bytes:
    return hashlib.sha256(f"{seed}|{key}|{example_id}".encode()).digest()


def select_examples(
    k: int, seed: int, key: str = "", pool: Sequence[FewShotExample] | None = None
) -> list[FewShotExample]:
    """Pick ``k`` examples, deterministically from ``seed`` and ``key`` (e.g. an episode id).

    Each example is ranked by a hash of (seed, key, its id), so the choice is stable across
    Python versions and adding an example to the file moves few choices.

    Raises:
        ConfigError: ``k`` exceeds the number of examples.
    """
    pool = few_shot_examples() if pool is None else pool
    if k > len(pool):
        raise ConfigError(f"k_shot={k} exceeds the {len(pool)} few-shot examples (0..{len(pool)})")
    return sorted(pool, key=lambda ex: _rank(seed, key, ex.id))[:k]


class LeakageFinding(Frozen):
    """A few-shot example too close to a benchmark task."""

    example_id: str
    task_id: str
    reason: str = Field(description="What overlaps: instruction or ARM skeleton.")
    overlap: float = Field(ge=0, le=1, description="Similarity that triggered the finding.")


def _content_words(text: str) -> set[str]:
    words = re.findall(r"[a-z0-9']+", text.lower())
    return {w for w in words if w not in _STOPWORDS}


def instruction_overlap(a: str, b: str) -> float:
    """Jaccard similarity of the content words of two instructions (1.0 = same words)."""
    wa, wb = _content_words(a), _content_words(b)
    if not wa or not wb:
        return 1.0 if a.strip().lower() == b.strip().lower() else 0.0
    return len(wa & wb) / len(wa | wb)


def _skeleton(steps: Iterable[tuple[str, str, str | None]]) -> Counter[tuple[str, str, str | None]]:
    return Counter(steps)


def skeleton_overlap(example: FewShotExample, task: TaskSpec) -> float:
    """Share of (skill, object, target) ARM steps the example has in common with the task."""
    ex = _skeleton((s.skill, s.object, s.target) for s in example.arm_steps)
    gt = _skeleton((s.skill, s.object, s.target) for s in task.arm_steps)
    common = sum((ex & gt).values())
    return common / max(sum(ex.values()), sum(gt.values()), 1)


def find_leakage(
    examples: Sequence[FewShotExample],
    tasks: Sequence[TaskSpec],
    *,
    max_instruction_overlap: float = 0.6,
    max_skeleton_overlap: float = 0.5,
) -> list[LeakageFinding]:
    """Examples whose instruction or ARM skeleton is (nearly) a benchmark task's.

    An instruction leaks when its content-word Jaccard similarity with either of a task's
    instructions reaches ``max_instruction_overlap``; a plan leaks when the shared
    (skill, object, target) steps reach ``max_skeleton_overlap`` of the longer skeleton.
    """
    found: list[LeakageFinding] = []
    for ex in examples:
        for task in tasks:
            texts = (task.instructions.explicit, task.instructions.implicit)
            words = max(instruction_overlap(ex.instruction, t) for t in texts)
            if words >= max_instruction_overlap:
                found.append(
                    LeakageFinding(
                        example_id=ex.id, task_id=task.id, reason="instruction", overlap=words
                    )
                )
            steps = skeleton_overlap(ex, task)
            if steps >= max_skeleton_overlap:
                found.append(
                    LeakageFinding(
                        example_id=ex.id, task_id=task.id, reason="arm_skeleton", overlap=steps
                    )
                )
    return found


def check_no_leakage(examples: Sequence[FewShotExample], tasks: Sequence[TaskSpec]) -> None:
    """Raise when any example leaks a benchmark task.

    Raises:
        DataFileError: Names the example file, the example and the task it overlaps.
    """
    found = find_leakage(examples, tasks)
    if found:
        first = found[0]
        more = f" (+{len(found) - 1} more)" if len(found) > 1 else ""
        raise DataFileError(
            str(prompts_dir() / EXAMPLES_FILE),
            f"example {first.example_id!r} overlaps task {first.task_id!r} "
            f"({first.reason}, {first.overlap:.2f}){more}",
        )
