"""The AIR-VLA planning metrics (docs/design.md#metrics, paper Appendix A.3) for one episode.

Documented choices where the paper is open:

* Invalid steps stay in place: they count toward K, never match a tasktype, a direction or a
  skill, and every object reference they make counts in K_obj (against S_obj) even when it
  names a GT object.
* S_loc gives each GT UAV step a credit ω against one predicted *UAV-typed* step (valid or
  not), or 0 when it has none; ``ScoringConfig.loc_alignment`` picks the pairing:

  - ``segment`` (default): both plans are cut at their ARM steps (predicted steps of tasktype
    ARM, valid or not). Segment k holds the moves between ARM steps k-1 and k (segment 0 the
    moves before the first ARM step) and a trailing segment the moves after the last one. ARM
    steps are matched by order (the k-th GT ARM step with the k-th predicted one, whatever
    their skills or objects), so GT segment k is compared with predicted segment k, and the
    trailing segments with each other; a GT segment whose ARM step has no k-th predicted
    counterpart gets 0 for all its moves. Within a segment pair, the horizontal GT moves are
    paired by order with the predicted horizontal moves and ``up``/``down`` with the predicted
    vertical moves, so a missing ``up`` does not shift the horizontal comparison. An invalid
    predicted UAV step counts in the sub-list of the direction it resolved to, and in the
    horizontal one when it resolved to none (an unknown direction such as "towards the cube" is
    a failed approach move, which is horizontal in the benchmark's plans): it occupies a slot
    and scores 0, as under ``order``. Predicted moves left without a GT partner (extra moves,
    moves in another segment) earn nothing and cost nothing here; S_plan penalises them.
  - ``order``: the i-th GT UAV step is paired with the i-th predicted UAV-typed step over the
    whole plan; an invalid UAV step (e.g. an unknown direction) occupies its index and scores
    0, so the model's later moves are not shifted onto earlier GT moves.

  Steps of unknown tasktype are neither moves nor segment separators. ω is 100 for the same
  direction, ``neighbour_credit`` (40) for sectors 45° apart (``frontright``↔``front`` wraps),
  else 0; ``up``/``down`` only match themselves.
* A GT with no UAV step / no object reference / no ARM step: see :class:`EmptyGtPolicy`.
* An output with no usable plan scores 0 everywhere (docs/design.md#metrics), whatever the policy.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Hashable, Iterable, Sequence

from vlm_bench.errors import ConfigError
from vlm_bench.scoring.taxonomy import classify_errors
from vlm_bench.types.parse import ParsedStep, ParseResult
from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS, ArmStep, Direction, UavStep
from vlm_bench.types.scores import EmptyGtPolicy, LocAlignment, PlanScores, ScoringConfig

DEFAULT_SCORING = ScoringConfig()
GtPlan = Sequence[UavStep | ArmStep]


def _clamp(value: float) -> float:
    return min(100.0, max(0.0, value))


def _overlap(a: Iterable[Hashable], b: Iterable[Hashable]) -> int:
    """Size of the multiset intersection of ``a`` and ``b``."""
    return sum((Counter(a) & Counter(b)).values())


def _empty_gt(prediction_has_some: bool, policy: EmptyGtPolicy) -> float:
    return 100.0 if policy is EmptyGtPolicy.FULL or not prediction_has_some else 0.0


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


def plan_score(m: int, k: int, n: int, alpha: float = 0.5) -> float:
    """S_plan = 100·[α·M/N + (1−α)·max(0, 1 − |K−N|/N)]."""
    return _clamp(100.0 * (alpha * m / n + (1.0 - alpha) * max(0.0, 1.0 - abs(k - n) / n)))


def type_matches(steps: Sequence[ParsedStep], gt: GtPlan) -> int:
    """M: positions i < min(K, N) where a valid predicted step has the GT step's tasktype."""
    return sum(p.valid and p.tasktype == g.tasktype for p, g in zip(steps, gt, strict=False))


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


def _segment_credits(steps: Sequence[ParsedStep], gt: GtPlan, neighbour: float) -> list[float]:
    gt_segments, pred_segments = _gt_segments(gt), _predicted_segments(steps)
    credits = [0.0] * sum(len(segment) for segment in gt_segments)
    n_gt_arm, n_pred_arm = len(gt_segments) - 1, len(pred_segments) - 1
    for k, segment in enumerate(gt_segments):
        if k == n_gt_arm:
            partner = pred_segments[-1]  # trailing with trailing
        elif k < n_pred_arm:
            partner = pred_segments[k]  # the moves before the k-th ARM step of each plan
        else:
            continue  # no k-th predicted ARM step: the segment's moves are missing
        for vertical in (False, True):
            gt_part = [(r, g) for r, g in segment if _is_vertical(g.direction) is vertical]
            pred_part = [p for p in partner if _is_vertical(p.direction) is vertical]
            for (rank, g), p in zip(gt_part, pred_part, strict=False):
                credits[rank] = _step_credit(p, g, neighbour)
    return credits


def loc_credits(
    steps: Sequence[ParsedStep],
    gt: GtPlan,
    neighbour: float = 40.0,
    alignment: LocAlignment = "segment",
) -> list[float]:
    """ω of each GT UAV step, in GT order, against its paired predicted UAV-typed step (or 0).

    Args:
        steps: The predicted steps, invalid ones included.
        gt: The GT plan.
        neighbour: ω for adjacent horizontal sectors.
        alignment: ``segment`` or ``order`` pairing (see the module docstring).
    """
    if alignment == "order":
        return _order_credits(steps, gt, neighbour)
    return _segment_credits(steps, gt, neighbour)


def _refs(step: ParsedStep | ArmStep) -> list[str]:
    return [r for r in (step.object, step.target) if r is not None]


def object_counts(steps: Sequence[ParsedStep], gt: GtPlan) -> tuple[int, int, int]:
    """(M_obj, K_obj, N_obj) over the multisets of ARM object/target references."""
    reference = [r for g in gt if isinstance(g, ArmStep) for r in _refs(g)]
    valid = [r for s in steps if s.valid and s.tasktype == "ARM" for r in _refs(s)]
    invalid = [r for s in steps if not s.valid for r in _refs(s)]
    m_obj = _overlap(valid, reference)
    return m_obj, len(valid) + len(invalid) - m_obj, len(reference)


def skill_counts(steps: Sequence[ParsedStep], gt: GtPlan) -> tuple[int, int]:
    """(M_skill, N_skill): multiset coverage of the GT ARM skills by valid predicted ARM skills."""
    reference = [g.skill for g in gt if isinstance(g, ArmStep)]
    predicted = [s.skill for s in steps if s.valid and s.tasktype == "ARM"]
    return _overlap(predicted, reference), len(reference)


def same_step(p: ParsedStep, g: UavStep | ArmStep) -> bool:
    """Exact match of a valid step: tasktype and direction, or object, skill and target."""
    if not p.valid or p.tasktype != g.tasktype:
        return False
    if isinstance(g, UavStep):
        return p.direction == g.direction
    return (p.object, p.skill, p.target) == (g.object, g.skill, g.target)


def is_success(steps: Sequence[ParsedStep], gt: GtPlan) -> bool:
    """Succ: same length and every step the same (distance ignored)."""
    return len(steps) == len(gt) and all(map(same_step, steps, gt))


def score_plan(
    parsed: ParseResult, gt: GtPlan, config: ScoringConfig = DEFAULT_SCORING
) -> PlanScores:
    """Score a parsed plan against the GT plan (docs/design.md#metrics).

    Args:
        parsed: The parser's result for the model output.
        gt: The episode's GT plan (at least one step).
        config: α, S_total weights, neighbour credit, S_loc alignment and the empty-GT policy.

    Returns:
        The scores with the counts behind them and the error taxonomy.

    Raises:
        ConfigError: The GT plan is empty (a data error, not a model error).
    """
    if not gt:
        raise ConfigError("the ground-truth plan is empty; cannot score against it")
    steps = parsed.steps if parsed.usable else ()
    n_move = sum(isinstance(g, UavStep) for g in gt)
    m, k, n = type_matches(steps, gt), len(steps), len(gt)
    credits = loc_credits(steps, gt, config.neighbour_credit, config.loc_alignment)
    m_obj, k_obj, n_obj = object_counts(steps, gt)
    m_skill, n_skill = skill_counts(steps, gt)
    if not parsed.usable:
        s_plan = s_loc = s_obj = s_skill = 0.0
    else:
        policy = config.empty_gt
        s_plan = plan_score(m, k, n, config.alpha)
        has_moves = any(s.tasktype == "UAV" for s in steps)
        s_loc = _clamp(sum(credits) / n_move) if n_move else _empty_gt(has_moves, policy)
        s_obj = _clamp(100.0 * (m_obj - k_obj) / n_obj) if n_obj else _empty_gt(k_obj > 0, policy)
        has_arm = any(s.tasktype == "ARM" for s in steps)
        s_skill = _clamp(100.0 * m_skill / n_skill) if n_skill else _empty_gt(has_arm, policy)
    w = config.weights
    total = _clamp(w.plan * s_plan + w.loc * s_loc + w.obj * s_obj + w.skill * s_skill)
    return PlanScores(
        s_plan=s_plan,
        s_loc=s_loc,
        s_obj=s_obj,
        s_skill=s_skill,
        s_total=total,
        succ=parsed.usable and is_success(steps, gt),
        m=m,
        k=k,
        n=n,
        n_move=n_move,
        loc_credit=tuple(credits),
        m_obj=m_obj,
        k_obj=k_obj,
        n_obj=n_obj,
        m_skill=m_skill,
        n_skill=n_skill,
        error_types=classify_errors(parsed, gt),
    )
