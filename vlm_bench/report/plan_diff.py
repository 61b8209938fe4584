"""GT and predicted plan side by side, aligned so that differing steps stand out.

Steps are compared as the success metric compares them (agent, direction or skill, object,
target; the optional distance is ignored) and aligned by the longest matching blocks
(:class:`difflib.SequenceMatcher`): a step the prediction changed sits beside the GT step it
replaces, a missing or extra step beside an empty cell. Invalid predicted steps never match.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from difflib import SequenceMatcher
from typing import Any, Literal

from vlm_bench.types.parse import ParsedStep

RowStatus = Literal["same", "changed", "missing", "extra"]
_FAILED_STEP = re.compile(r"^step (\d+):")


@dataclass(frozen=True)
class DiffRow:
    """One row of the side-by-side plan."""

    gt: str | None
    """The GT step as text (None: the prediction has an extra step here)."""
    pred: str | None
    """The predicted step as text (None: the prediction misses this GT step)."""
    status: RowStatus
    pred_index: int | None = None
    """The predicted step's index in the model's plan (execution failures name it)."""
    errors: tuple[str, ...] = ()
    """Parse codes of the predicted step."""


def gt_text(step: dict[str, Any]) -> str:
    """``UAV front`` / ``ARM pick gray_cube`` / ``ARM place cube → basket`` (paper JSON)."""
    if step.get("tasktype") == "UAV":
        distance = step.get("distance")
        return f"UAV {step.get('direction')}" + (f" {distance} m" if distance else "")
    target = step.get("target")
    text = f"ARM {step.get('skill')} {step.get('object')}"
    return text + (f" → {target}" if target else "")


def gt_key(step: dict[str, Any]) -> tuple[object, ...]:
    """What the success metric compares of a GT step."""
    if step.get("tasktype") == "UAV":
        return ("UAV", step.get("direction"))
    return ("ARM", step.get("skill"), step.get("object"), step.get("target"))


def pred_text(step: ParsedStep) -> str:
    """A parsed step as text; an invalid one as the JSON the model wrote."""
    if not step.valid:
        return "invalid: " + json.dumps(step.raw, ensure_ascii=False)[:120]
    if step.tasktype == "UAV":
        return f"UAV {step.direction}" + (f" {step.distance:g} m" if step.distance else "")
    text = f"ARM {step.skill} {step.object}"
    return text + (f" → {step.target}" if step.target else "")


def pred_key(step: ParsedStep) -> tuple[object, ...]:
    """What the success metric compares of a predicted step (unique for an invalid one)."""
    if not step.valid:
        return ("invalid", step.index)
    if step.tasktype == "UAV":
        return ("UAV", step.direction)
    return ("ARM", step.skill, step.object, step.target)


def plan_diff(gt: Sequence[dict[str, Any]], pred: Sequence[ParsedStep]) -> list[DiffRow]:
    """Rows of the GT and predicted plans, aligned (see the module docstring)."""
    a, b = [gt_key(s) for s in gt], [pred_key(s) for s in pred]
    rows: list[DiffRow] = []

    def predicted(j: int, status: RowStatus, g: str | None) -> DiffRow:
        step = pred[j]
        return DiffRow(g, pred_text(step), status, step.index, tuple(step.errors))

    for op, i1, i2, j1, j2 in SequenceMatcher(a=a, b=b, autojunk=False).get_opcodes():
        if op == "equal":
            rows += [predicted(j1 + k, "same", gt_text(gt[i1 + k])) for k in range(i2 - i1)]
            continue
        pairs = min(i2 - i1, j2 - j1)
        rows += [predicted(j1 + k, "changed", gt_text(gt[i1 + k])) for k in range(pairs)]
        rows += [DiffRow(gt_text(gt[i]), None, "missing") for i in range(i1 + pairs, i2)]
        rows += [predicted(j, "extra", None) for j in range(j1 + pairs, j2)]
    return rows


def failed_step(reason: str | None) -> int | None:
    """The plan step an execution failure names (``step 2: ...``), if any."""
    match = _FAILED_STEP.match(reason or "")
    return int(match.group(1)) if match else None
