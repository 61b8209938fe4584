"""Planning metrics of the AIR-VLA paper (S_plan, S_loc, S_obj, S_skill, S_total, Succ) and an
error taxonomy, computed from a :class:`~vlm_bench.types.parse.ParseResult` and the GT plan.

Scoring never imports the simulator.
"""

from vlm_bench.scoring.loc_pairing import common_subsequence, direction_credit, loc_credits
from vlm_bench.scoring.metrics import (
    DEFAULT_SCORING,
    is_success,
    object_counts,
    plan_score,
    same_step,
    score_plan,
    skill_counts,
    type_matches,
)
from vlm_bench.scoring.taxonomy import align, classify_errors, is_reordered

__all__ = [
    "DEFAULT_SCORING",
    "align",
    "classify_errors",
    "common_subsequence",
    "direction_credit",
    "is_reordered",
    "is_success",
    "loc_credits",
    "object_counts",
    "plan_score",
    "same_step",
    "score_plan",
    "skill_counts",
    "type_matches",
]
