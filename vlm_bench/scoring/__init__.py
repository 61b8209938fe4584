"""Planning metrics of the AIR-VLA paper (S_plan, S_loc, S_obj, S_skill, S_total, Succ) and an
error taxonomy, computed from a :class:`~vlm_bench.types.parse.ParseResult` and the GT plan.

Scoring never imports the simulator.
"""

from vlm_bench.scoring.loc_pairing import common_subsequence, direction_credit, loc_credits
from vlm_bench.scoring.metrics import plan_score, score_plan
from vlm_bench.scoring.taxonomy import align, classify_errors

__all__ = [
    "align",
    "classify_errors",
    "common_subsequence",
    "direction_credit",
    "loc_credits",
    "plan_score",
    "score_plan",
]
