"""The task's scorer: :func:`vlm_bench.score_answer` on the answer to round 0, the paper's
metrics per suite and overall (the unweighted mean of the suites, as the paper's Overall), and
Succ@k of a closed loop.

Values are on the report's scale: S_* in [0, 100], Succ and Succ@k in percent (0 or 100 per
episode), so the means are the numbers ``vlm-bench report`` prints.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from vlm_bench.scoring.answer import score_answer

if TYPE_CHECKING:
    from inspect_ai.scorer import Scorer

PAPER_METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ")
"""The paper's metrics, named as in the report."""
ROUND_ZERO = "vlm_bench_round0"
"""Metadata key where the closed-loop solver keeps round 0's answer (the scored one)."""
LOOP_OUTCOME = "vlm_bench_loop"
"""Metadata key where the closed-loop solver keeps the episode's Succ@k list."""


def succ_at_names(max_rounds: int) -> list[str]:
    """``Succ@0`` .. ``Succ@K``."""
    return [f"Succ@{k}" for k in range(max_rounds + 1)]


def score_values(metadata: dict[str, Any], answer: str) -> tuple[dict[str, float], list[str]]:
    """The paper's metrics of one answer (report scale) and its error tags."""
    scored = score_answer(metadata, answer)
    scores = scored.scores
    values = {
        "S_plan": scores.s_plan,
        "S_loc": scores.s_loc,
        "S_obj": scores.s_obj,
        "S_skill": scores.s_skill,
        "S_total": scores.s_total,
        "Succ": 100.0 if scores.succ else 0.0,
    }
    return values, list(scored.error_tags)


def plan_scorer(max_rounds: int | None = None) -> Scorer:
    """The scorer of ``vlm_bench/aerial``: the paper's metrics (and Succ@0..K with
    ``max_rounds``), each grouped by suite with ``overall`` the mean of the suites."""
    from inspect_ai.scorer import Score, Target, grouped, mean, scorer
    from inspect_ai.solver import TaskState

    names = [*PAPER_METRICS, *(succ_at_names(max_rounds) if max_rounds is not None else [])]
    metrics: Any = {
        name: [grouped(mean(), "suite", all="groups", all_label="overall")] for name in names
    }

    @scorer(metrics=metrics)
    def vlm_bench_plan() -> Scorer:
        async def score(state: TaskState, target: Target) -> Score:
            answer = state.metadata.get(ROUND_ZERO, state.output.completion)
            values, tags = score_values(state.metadata, answer)
            outcome = state.metadata.get(LOOP_OUTCOME)
            if max_rounds is not None:
                succ = list(outcome["succ_at"]) if outcome else [False] * (max_rounds + 1)
                values.update(
                    {name: 100.0 if ok else 0.0 for name, ok in zip(names[6:], succ, strict=True)}
                )
            return Score(
                value=values,
                answer=answer,
                explanation=", ".join(tags) or "no errors",
                metadata={"error_tags": tags, **({"loop": outcome} if outcome else {})},
            )

        return score

    return vlm_bench_plan()
