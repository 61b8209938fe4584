"""The dataset row: one episode (task × seed × instruction variant) holding exactly what a run
with the same options sends (system text, user text, PNG images) and what scoring needs (object
ids, GT plan). Light: importable without the simulator (harness tasks read rows with it).

The row's fields are the dataset's columns, but for ``images``, which becomes one
``image_<view>`` column per view (:func:`image_column`).
"""

from __future__ import annotations

import re
from typing import Literal

from pydantic import Field

from vlm_bench.types.base import Frozen
from vlm_bench.types.prompt import VIEWS, View
from vlm_bench.types.task import InstructionVariant

_PLACEHOLDER = re.compile(r"^<image:(" + "|".join(VIEWS) + r")>$")


class GtStep(Frozen):
    """One GT step in the paper's format, every field present (None where it does not apply)."""

    subtask: int = Field(ge=0, description="Step index, from 0.")
    tasktype: Literal["UAV", "ARM"] = Field(description="UAV move or ARM skill.")
    direction: str | None = Field(default=None, description="UAV: body-frame direction.")
    distance: float | None = Field(default=None, description="UAV: distance (m), if given.")
    object: str | None = Field(default=None, description="ARM: object id the skill acts on.")
    skill: str | None = Field(default=None, description="ARM: skill name.")
    target: str | None = Field(default=None, description="ARM: second object (push), if any.")


class DatasetRow(Frozen):
    """One episode of the benchmark as a harness sees it (one dataset row)."""

    key: str = Field(description="Episode key task_id/seed/variant (records, score_answer).")
    benchmark_version: int = Field(description="Benchmark version the row belongs to.")
    task_id: str = Field(description="Task id.")
    suite: str = Field(description="Task suite (base_manipulation, object_spatial, ...).")
    seed: int = Field(ge=0, description="Episode seed.")
    instruction: InstructionVariant = Field(description="Instruction variant.")
    instruction_text: str = Field(description="The instruction itself (also in user).")
    system: str = Field(description="System message exactly as a run sends it.")
    user: str = Field(
        description="User turn exactly as a run sends it: text parts, and <image:view> on "
        "its own line where each image goes."
    )
    views: tuple[View, ...] = Field(description="Views of the user turn's images, in order.")
    images: dict[str, bytes] = Field(
        repr=False, description="PNG bytes by view, as a run sends them (column image_<view>)."
    )
    objects: tuple[str, ...] = Field(description="Object and part ids a plan may reference.")
    gt_plan: str = Field(description="GT plan as JSON in the paper's format.")
    gt_steps: tuple[GtStep, ...] = Field(description="GT plan as structured steps.")
    prompt_hash: str = Field(description="Prompt hash a run's record of this episode stores.")
    example_ids: tuple[str, ...] = Field(description="Few-shot examples in the system text.")


def image_column(view: str) -> str:
    """The dataset column holding a view's image: ``image_<view>``."""
    return f"image_{view}"


def user_parts(user: str) -> list[tuple[Literal["text", "image"], str]]:
    """A row's ``user`` text back as the parts a run sends: ``("text", text)`` and
    ``("image", view)`` in order (text parts never hold a placeholder line, so this is exact)."""
    parts: list[tuple[Literal["text", "image"], str]] = []
    lines: list[str] = []
    for line in user.split("\n"):
        match = _PLACEHOLDER.match(line)
        if match is None:
            lines.append(line)
            continue
        if lines:
            parts.append(("text", "\n".join(lines)))
            lines = []
        parts.append(("image", match.group(1)))
    if lines:
        parts.append(("text", "\n".join(lines)))
    return parts
