"""Planning scores of one episode (AIR-VLA Appendix A.3 metrics) and their configuration."""

from __future__ import annotations

import math
from enum import StrEnum
from typing import Literal

from pydantic import Field, model_validator

from vlm_bench.types.base import Frozen


class EmptyGtPolicy(StrEnum):
    """How a metric scores when the GT has nothing of its kind (no UAV move, no object, no skill).

    The benchmark's episodes always have a UAV move and ARM steps; this matters for custom tasks.
    """

    STRICT = "strict"
    """100 when the prediction has nothing of that kind either, else 0 (the natural limit of the
    formulas: extra moves / references / ARM steps are wrong)."""
    FULL = "full"
    """Always 100: nothing to get right (extra steps are still penalised by S_plan)."""


LocAlignment = Literal["content", "segment", "order"]
"""How S_loc pairs predicted UAV steps with GT UAV steps (see :mod:`vlm_bench.scoring.loc_pairing`):
``content`` compares the moves leading to each GT ARM step with those leading to the predicted
ARM step matched to it by a longest common subsequence on (skill, object), horizontal with
horizontal and vertical with vertical, each by order; ``segment`` does the same with ARM steps
matched by order (the k-th with the k-th); ``order`` pairs the i-th GT move with the i-th
predicted UAV step (the paper read literally)."""


class ScoreWeights(Frozen):
    """Weights of S_total; non-negative and summing to 1 so that S_total stays in [0, 100]."""

    plan: float = Field(default=0.25, ge=0, le=1, description="Weight of S_plan.")
    loc: float = Field(default=0.25, ge=0, le=1, description="Weight of S_loc.")
    obj: float = Field(default=0.25, ge=0, le=1, description="Weight of S_obj.")
    skill: float = Field(default=0.25, ge=0, le=1, description="Weight of S_skill.")

    @model_validator(mode="after")
    def _sum_to_one(self) -> ScoreWeights:
        total = self.plan + self.loc + self.obj + self.skill
        if not math.isclose(total, 1.0, abs_tol=1e-9):
            raise ValueError(f"score weights must sum to 1, got {total}")
        return self


class ScoringConfig(Frozen):
    """The open choices of the metrics (docs/design.md#metrics); defaults follow the paper except
    ``loc_alignment``, whose default ``content`` replaces the paper's literal order pairing.

    ``loc_alignment`` was added after the first release. A run manifest written before it
    lacks the field and loads as ``order`` (how those runs were scored), so rescoring or resuming
    an older run reproduces its S_loc; a manifest that names ``segment`` (benchmark version 1's
    default) keeps it; a new run scores by ``content`` unless told otherwise.
    """

    alpha: float = Field(default=0.5, ge=0, le=1, description="Type-accuracy weight in S_plan.")
    weights: ScoreWeights = Field(default_factory=ScoreWeights, description="S_total weights.")
    neighbour_credit: float = Field(
        default=40.0, ge=0, le=100, description="S_loc credit for a neighbouring sector (45°)."
    )
    empty_gt: EmptyGtPolicy = Field(
        default=EmptyGtPolicy.STRICT,
        description="S_loc/S_obj/S_skill when the GT has no moves/references/ARM skills.",
    )
    loc_alignment: LocAlignment = Field(
        default="content",
        description="S_loc pairing: 'content' (moves before ARM steps matched on skill and "
        "object, horizontal and vertical apart), 'segment' (ARM steps matched by order) or "
        "'order' (i-th GT move vs i-th predicted UAV step, the paper's).",
    )


class ErrorType(StrEnum):
    """Planning error categories found by aligning the prediction with the GT."""

    NO_PLAN = "no_plan"
    """The output held no usable plan."""
    WRONG_TYPE = "wrong_type"
    """An aligned step has the other (or an unknown) tasktype."""
    WRONG_DIRECTION = "wrong_direction"
    """An aligned UAV step moves in another direction (or an invalid one)."""
    WRONG_OBJECT = "wrong_object"
    """An aligned ARM step acts on another object or target."""
    WRONG_SKILL = "wrong_skill"
    """An aligned ARM step uses another (or an invalid) skill."""
    MISSING_STEP = "missing_step"
    """A GT step has no counterpart in the prediction."""
    EXTRA_STEP = "extra_step"
    """A predicted step has no counterpart in the GT."""
    WRONG_ORDER = "wrong_order"
    """The ARM steps are the GT's (same multiset) in another order."""
    MISSING_APPROACH = "missing_approach"
    """An ARM step whose GT counterpart is preceded by a UAV move (since the previous ARM step)
    has no UAV move before it in the prediction (since the previous ARM step)."""


class PlanScores(Frozen):
    """All planning metrics of one episode, in [0, 100], with the counts behind them."""

    s_plan: float = Field(ge=0, le=100, description="Process planning (type accuracy + length).")
    s_loc: float = Field(ge=0, le=100, description="Spatial navigation (UAV directions).")
    s_obj: float = Field(ge=0, le=100, description="Object grounding (hallucinations penalised).")
    s_skill: float = Field(ge=0, le=100, description="Skill selection (multiset coverage).")
    s_total: float = Field(ge=0, le=100, description="Weighted sum of the four.")
    succ: bool = Field(description="The normalised plan equals the GT exactly (distance ignored).")
    m: int = Field(ge=0, description="M: positions < min(K, N) with the GT's tasktype.")
    k: int = Field(ge=0, description="K: predicted steps, invalid ones included.")
    n: int = Field(ge=1, description="N: GT steps.")
    n_move: int = Field(ge=0, description="N_move: GT UAV steps.")
    n_move_pred: int = Field(
        default=0, ge=0, description="UAV-typed predicted steps (valid or not); 0 in old records."
    )
    s_loc_precision: float = Field(
        default=0.0,
        ge=0,
        le=100,
        description="S_loc's credits over max(N_move, n_move_pred): padding no longer pays; "
        "S_loc when the GT has no move. Absent (0) in records from before version 3.",
    )
    loc_credit: tuple[float, ...] = Field(default=(), description="ω of each GT UAV step.")
    m_obj: int = Field(ge=0, description="M_obj: predicted object references matching the GT.")
    k_obj: int = Field(ge=0, description="K_obj: wrong, hallucinated or invalid references.")
    n_obj: int = Field(ge=0, description="N_obj: GT object references (object and target).")
    m_skill: int = Field(ge=0, description="M_skill: GT ARM skills covered by the prediction.")
    n_skill: int = Field(ge=0, description="N_skill: GT ARM skills.")
    error_types: tuple[ErrorType, ...] = Field(default=(), description="Taxonomy, see ErrorType.")
