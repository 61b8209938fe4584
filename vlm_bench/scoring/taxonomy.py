"""Error taxonomy: align the predicted steps with the GT steps and name what differs.

The alignment is a weighted edit distance over steps (insertion and deletion cost 1; a
substitution costs 0 for an exact match, 0.75 or 1 for a same-type step differing in one or two
aspects, 1.5 across types), so a step of the wrong type in the right place reads as
``wrong_type`` while a shifted plan reads as ``missing_step``/``extra_step``. Categories are
returned once each, in :class:`ErrorType` order.

``wrong_order``: the valid predicted ARM steps are the GT's ARM steps as a multiset but in
another order. It replaces the ARM-step ``wrong_skill``/``wrong_object``/``missing_step``/
``extra_step`` findings that the reordering causes in the alignment.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from vlm_bench.types.parse import ParsedStep, ParseResult
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.scores import ErrorType

GtStep = UavStep | ArmStep
_INDEL = 1.0
_CROSS_TYPE = 1.5


@dataclass(frozen=True)
class Op:
    """One alignment operation: a pair, an extra predicted step, or a missing GT step."""

    pred: int | None
    gt: int | None


def _aspects(p: ParsedStep, g: GtStep) -> tuple[bool, bool]:
    """(skill or direction differs, object/target differs) for same-type steps."""
    if isinstance(g, UavStep):
        return (not p.valid or p.direction != g.direction), False
    return p.skill != g.skill, (p.object, p.target) != (g.object, g.target)


def _cost(p: ParsedStep, g: GtStep) -> float:
    if p.tasktype != g.tasktype:
        return _CROSS_TYPE
    first, second = _aspects(p, g)
    if not p.valid and not (first or second):
        first = True  # an invalid step never matches exactly
    differences = int(first) + int(second)
    return 0.0 if differences == 0 else 0.5 + 0.25 * differences


def align(steps: Sequence[ParsedStep], gt: Sequence[GtStep]) -> list[Op]:
    """Minimum-cost alignment of predicted and GT steps, in order."""
    k, n = len(steps), len(gt)
    cost = [[0.0] * (n + 1) for _ in range(k + 1)]
    for i in range(1, k + 1):
        cost[i][0] = i * _INDEL
    for j in range(1, n + 1):
        cost[0][j] = j * _INDEL
    for i in range(1, k + 1):
        for j in range(1, n + 1):
            cost[i][j] = min(
                cost[i - 1][j - 1] + _cost(steps[i - 1], gt[j - 1]),
                cost[i - 1][j] + _INDEL,
                cost[i][j - 1] + _INDEL,
            )
    ops: list[Op] = []
    i, j = k, n
    while i or j:
        if i and j and cost[i][j] == cost[i - 1][j - 1] + _cost(steps[i - 1], gt[j - 1]):
            ops.append(Op(i - 1, j - 1))
            i, j = i - 1, j - 1
        elif i and cost[i][j] == cost[i - 1][j] + _INDEL:
            ops.append(Op(i - 1, None))
            i -= 1
        else:
            ops.append(Op(None, j - 1))
            j -= 1
    return ops[::-1]


def _move_since_last_arm(tasktypes: Sequence[str | None], index: int) -> bool:
    """True when a UAV step lies between the previous ARM step (or the start) and ``index``."""
    for tasktype in reversed(tasktypes[:index]):
        if tasktype == "ARM":
            return False
        if tasktype == "UAV":
            return True
    return False


def _arm_signature(step: ParsedStep | ArmStep) -> tuple[str | None, str | None, str | None]:
    return step.skill, step.object, step.target


def is_reordered(steps: Sequence[ParsedStep], gt: Sequence[GtStep]) -> bool:
    """The valid predicted ARM steps equal the GT ARM steps as a multiset, not as a sequence."""
    predicted = [_arm_signature(s) for s in steps if s.valid and s.tasktype == "ARM"]
    reference = [_arm_signature(g) for g in gt if isinstance(g, ArmStep)]
    return Counter(predicted) == Counter(reference) and predicted != reference


def classify_errors(parsed: ParseResult, gt: Sequence[GtStep]) -> tuple[ErrorType, ...]:
    """Error categories of the prediction against the GT (empty for an exact plan).

    Args:
        parsed: The parser's result.
        gt: The GT plan.

    Returns:
        Each category found, once, in :class:`ErrorType` order; ``(no_plan,)`` when the output
        held no usable plan.
    """
    if not parsed.usable:
        return (ErrorType.NO_PLAN,)
    steps = parsed.steps
    reordered = is_reordered(steps, gt)
    found: set[ErrorType] = set()
    if reordered:
        found.add(ErrorType.WRONG_ORDER)
    pred_types = [s.tasktype for s in steps]
    gt_types: list[str | None] = [g.tasktype for g in gt]
    for op in align(steps, gt):
        if op.gt is None and op.pred is not None:
            p = steps[op.pred]
            if not (reordered and p.valid and p.tasktype == "ARM"):
                found.add(ErrorType.EXTRA_STEP)
        elif op.pred is None and op.gt is not None:
            if not (reordered and isinstance(gt[op.gt], ArmStep)):
                found.add(ErrorType.MISSING_STEP)
        elif op.pred is not None and op.gt is not None:
            found.update(_pair_errors(steps[op.pred], gt[op.gt], reordered))
            if (
                isinstance(gt[op.gt], ArmStep)
                and steps[op.pred].tasktype == "ARM"
                and _move_since_last_arm(gt_types, op.gt)
                and not _move_since_last_arm(pred_types, op.pred)
            ):
                found.add(ErrorType.MISSING_APPROACH)
    return tuple(e for e in ErrorType if e in found)


def _pair_errors(p: ParsedStep, g: GtStep, reordered: bool) -> set[ErrorType]:
    if p.tasktype != g.tasktype:
        return {ErrorType.WRONG_TYPE}
    first, second = _aspects(p, g)
    if isinstance(g, UavStep):
        return {ErrorType.WRONG_DIRECTION} if first else set()
    if reordered and p.valid:
        return set()
    out: set[ErrorType] = set()
    if first or (not p.valid and not second):
        out.add(ErrorType.WRONG_SKILL)
    if second:
        out.add(ErrorType.WRONG_OBJECT)
    return out
