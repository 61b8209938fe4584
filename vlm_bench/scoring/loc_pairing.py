"""S_loc's pairing of GT UAV moves with predicted UAV steps (docs/metrics.md#s_loc).

Each GT UAV step gets a credit ω against one predicted *UAV-typed* step (valid or not), or 0
when it has none; ``ScoringConfig.loc_alignment`` picks the pairing:

- ``content`` (default) and ``segment``: both plans are cut at their ARM steps (predicted steps
  of tasktype ARM, valid or not). Segment k holds the moves between ARM steps k-1 and k (segment
  0 the moves before the first ARM step) and a trailing segment the moves after the last one.
  GT segment k is compared with the segment of the predicted ARM step matched to GT ARM step k,
  and the trailing segments with each other; a GT ARM step without a match gets 0 for all its
  segment's moves. The two differ in how ARM steps are matched:

  - ``content``: a longest common subsequence of the two ARM-step sequences on (skill, object),
    so an inserted or missing ARM step does not shift the later segments. An invalid predicted
    ARM step matches nothing. Among equally long matchings the earliest GT steps are matched,
    each with the earliest predicted step left (the lexicographically smallest list of pairs).
  - ``segment``: by order, the k-th GT ARM step with the k-th predicted one, whatever their
    skills or objects.

  Within a segment pair, the horizontal GT moves are paired by order with the predicted
  horizontal moves and ``up``/``down`` with the predicted vertical moves, so a missing ``up``
  does not shift the horizontal comparison. An invalid predicted UAV step counts in the
  sub-list of the direction it resolved to, and in the horizontal one when it resolved to none
  (an unknown direction such as "towards the cube" is a failed approach move, which is
  horizontal in the benchmark's plans): it occupies a slot and scores 0, as under ``order``.
  Predicted moves left without a GT partner (extra moves, moves in another segment) earn
  nothing and cost nothing here; S_plan penalises them.
- ``order``: the i-th GT UAV step is paired with the i-th predicted UAV-typed step over the
  whole plan; an invalid UAV step (e.g. an unknown direction) occupies its index and scores 0,
  so the model's later moves are not shifted onto earlier GT moves.

Steps of unknown tasktype are neither moves nor segment separators. ω is 100 for the same
direction, ``neighbour_credit`` (40) for sectors 45° apart (``frontright``↔``front`` wraps),
else 0; ``up``/``down`` only match themselves.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence

from vlm_bench.types.parse import ParsedStep
from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS, ArmStep, Direction, UavStep
from vlm_bench.types.scores import LocAlignment

GtPlan = Sequence[UavStep | ArmStep]


def direction_credit(predicted: Direction | None, gt: Direction, neighbour: float = 40.0) -> float:
    """ω(Δθ): 100 same direction, ``neighbour`` for adjacent sectors, else 0 (None scores 0)."""
    if predicted is None:
        return 0.0
    if predicted == gt:
        return 100.0
    if predicted.is_horizontal and gt.is_horizontal:
        gap = abs(HORIZONTAL_DIRECTIONS.index(predicted) - HORIZONTAL_DIRECTIONS.index(gt))
        if min(gap, len(HORIZONTAL_DIRECTIONS) - gap) == 1:
            return neighbour
    return 0.0


def _step_credit(p: ParsedStep | None, g: UavStep, neighbour: float) -> float:
    """ω of one GT move against its partner (an absent or invalid partner scores 0)."""
    ok = p is not None and p.valid
    return direction_credit(p.direction if ok and p else None, g.direction, neighbour)


def _order_credits(steps: Sequence[ParsedStep], gt: GtPlan, neighbour: float) -> list[float]:
    predicted = [s for s in steps if s.tasktype == "UAV"]
    moves = [g for g in gt if isinstance(g, UavStep)]
    return [
        _step_credit(predicted[i] if i < len(predicted) else None, g, neighbour)
        for i, g in enumerate(moves)
    ]


def common_subsequence(gt: Sequence[Hashable], predicted: Sequence[Hashable | None]) -> list[int]:
    """A longest common subsequence of ``gt`` and ``predicted`` as, for each GT item, the index
    of its predicted partner or -1; ``None`` in ``predicted`` matches nothing. Ties go to the
    earliest pairs: the list of matched (GT, predicted) index pairs is lexicographically the
    smallest among the longest ones."""
    n, m = len(gt), len(predicted)
    # best[i][j]: the length of a longest common subsequence of gt[i:] and predicted[j:].
    best = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n - 1, -1, -1):
        for j in range(m - 1, -1, -1):
            same = predicted[j] is not None and gt[i] == predicted[j]
            best[i][j] = best[i + 1][j + 1] + 1 if same else max(best[i + 1][j], best[i][j + 1])
    partner, i, j = [-1] * n, 0, 0
    while i < n and j < m:
        if (
            predicted[j] is not None
            and gt[i] == predicted[j]
            and best[i][j] == best[i + 1][j + 1] + 1
        ):
            partner[i] = j
            i, j = i + 1, j + 1
        elif best[i][j + 1] == best[i][j]:
            j += 1  # predicted j is not needed: GT i may still meet a later one
        else:
            i += 1
    return partner


def _arm_key(step: ParsedStep | ArmStep) -> tuple[str | None, str | None] | None:
    """What ARM steps are matched on: (skill, object); an invalid predicted step has none."""
    if isinstance(step, ParsedStep) and not step.valid:
        return None
    return (step.skill, step.object)


def _arm_partners(steps: Sequence[ParsedStep], gt: GtPlan, alignment: LocAlignment) -> list[int]:
    """For each GT ARM step, the index of its partner among the predicted ARM-typed steps, or
    -1 (``segment``: by order; ``content``: see :func:`common_subsequence`)."""
    gt_arm = [g for g in gt if isinstance(g, ArmStep)]
    pred_arm = [s for s in steps if s.tasktype == "ARM"]
    if alignment == "segment":
        return [k if k < len(pred_arm) else -1 for k in range(len(gt_arm))]
    return common_subsequence([_arm_key(g) for g in gt_arm], [_arm_key(s) for s in pred_arm])


def _gt_segments(gt: GtPlan) -> list[list[tuple[int, UavStep]]]:
    """The GT moves (with their rank among the GT moves) before each ARM step, then the
    trailing ones: one more segment than ARM steps."""
    out: list[list[tuple[int, UavStep]]] = [[]]
    rank = 0
    for g in gt:
        if isinstance(g, UavStep):
            out[-1].append((rank, g))
            rank += 1
        else:
            out.append([])
    return out


def _predicted_segments(steps: Sequence[ParsedStep]) -> list[list[ParsedStep]]:
    """The UAV-typed steps before each ARM-typed step (valid or not), then the trailing ones."""
    out: list[list[ParsedStep]] = [[]]
    for s in steps:
        if s.tasktype == "ARM":
            out.append([])
        elif s.tasktype == "UAV":
            out[-1].append(s)
    return out


def _is_vertical(direction: Direction | None) -> bool:
    """Vertical sub-list: ``up``/``down``; an unresolved direction counts as horizontal."""
    return direction is not None and not direction.is_horizontal


def _segment_credits(
    steps: Sequence[ParsedStep], gt: GtPlan, neighbour: float, alignment: LocAlignment
) -> list[float]:
    gt_segments, pred_segments = _gt_segments(gt), _predicted_segments(steps)
    # The trailing segments meet whatever the ARM steps did.
    partners = [*_arm_partners(steps, gt, alignment), len(pred_segments) - 1]
    credits = [0.0] * sum(len(segment) for segment in gt_segments)
    for segment, partner in zip(gt_segments, partners, strict=True):
        if partner < 0:
            continue  # the GT ARM step has no predicted partner: its moves are missing
        for vertical in (False, True):
            gt_part = [(r, g) for r, g in segment if _is_vertical(g.direction) is vertical]
            pred_part = [p for p in pred_segments[partner] if _is_vertical(p.direction) is vertical]
            for (rank, g), p in zip(gt_part, pred_part, strict=False):
                credits[rank] = _step_credit(p, g, neighbour)
    return credits


def loc_credits(
    steps: Sequence[ParsedStep],
    gt: GtPlan,
    neighbour: float = 40.0,
    alignment: LocAlignment = "content",
) -> list[float]:
    """ω of each GT UAV step, in GT order, against its paired predicted UAV-typed step (or 0).

    Args:
        steps: The predicted steps, invalid ones included.
        gt: The GT plan.
        neighbour: ω for adjacent horizontal sectors.
        alignment: ``content``, ``segment`` or ``order`` pairing (see the module docstring).
    """
    if alignment == "order":
        return _order_credits(steps, gt, neighbour)
    return _segment_credits(steps, gt, neighbour, alignment)
