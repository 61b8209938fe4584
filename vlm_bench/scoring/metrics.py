"""The AIR-VLA planning metrics (docs/design.md#metrics, paper Appendix A.3) for one episode.

Documented choices where the paper is open:

* Invalid steps stay in place: they count toward K, never match a tasktype, a direction or a
  skill, and every object reference they make counts in K_obj (against S_obj) even when it
  names a GT object.
* S_loc gives each GT UAV step a credit ω against one predicted UAV-typed step, or 0; the
  pairing (``ScoringConfig.loc_alignment``: ``content`` by default, ``segment``, ``order``) is
  :mod:`vlm_bench.scoring.loc_pairing`.
* A GT with no UAV step / no object reference / no ARM step: see :class:`EmptyGtPolicy`.
* S_loc_prec, S_loc's diagnostic against padding, divides the same credits by
  max(N_move, predicted UAV steps); with no GT move it is S_loc (the empty-GT policy).
* An output with no usable plan scores 0 everywhere (docs/design.md#metrics), whatever the policy.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Hashable, Iterable, Sequence

from vlm_bench.errors import ConfigError
from vlm_bench.scoring.loc_pairing import loc_credits
from vlm_bench.scoring.taxonomy import classify_errors
from vlm_bench.types.parse import ParsedStep, ParseResult
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.scores import EmptyGtPolicy, PlanScores, ScoringConfig

DEFAULT_SCORING = ScoringConfig()
GtPlan = Sequence[UavStep | ArmStep]


def _clamp(value: float) -> float:
    return min(100.0, max(0.0, value))


def _overlap(a: Iterable[Hashable], b: Iterable[Hashable]) -> int:
    """Size of the multiset intersection of ``a`` and ``b``."""
    return sum((Counter(a) & Counter(b)).values())


def _empty_gt(prediction_has_some: bool, policy: EmptyGtPolicy) -> float:
    return 100.0 if policy is EmptyGtPolicy.FULL or not prediction_has_some else 0.0


def plan_score(m: int, k: int, n: int, alpha: float = 0.5) -> float:
    """S_plan = 100·[α·M/N + (1−α)·max(0, 1 − |K−N|/N)]."""
    return _clamp(100.0 * (alpha * m / n + (1.0 - alpha) * max(0.0, 1.0 - abs(k - n) / n)))


def type_matches(steps: Sequence[ParsedStep], gt: GtPlan) -> int:
    """M: positions i < min(K, N) where a valid predicted step has the GT step's tasktype."""
    return sum(p.valid and p.tasktype == g.tasktype for p, g in zip(steps, gt, strict=False))


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
    n_move_pred = sum(s.tasktype == "UAV" for s in steps)
    m, k, n = type_matches(steps, gt), len(steps), len(gt)
    credits = loc_credits(steps, gt, config.neighbour_credit, config.loc_alignment)
    m_obj, k_obj, n_obj = object_counts(steps, gt)
    m_skill, n_skill = skill_counts(steps, gt)
    if not parsed.usable:
        s_plan = s_loc = s_loc_precision = s_obj = s_skill = 0.0
    else:
        policy = config.empty_gt
        s_plan = plan_score(m, k, n, config.alpha)
        has_moves = any(s.tasktype == "UAV" for s in steps)
        s_loc = _clamp(sum(credits) / n_move) if n_move else _empty_gt(has_moves, policy)
        s_loc_precision = _clamp(sum(credits) / max(n_move, n_move_pred)) if n_move else s_loc
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
        n_move_pred=n_move_pred,
        s_loc_precision=s_loc_precision,
        loc_credit=tuple(credits),
        m_obj=m_obj,
        k_obj=k_obj,
        n_obj=n_obj,
        m_skill=m_skill,
        n_skill=n_skill,
        error_types=classify_errors(parsed, gt),
    )
