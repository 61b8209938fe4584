"""A closed-loop episode's replans as stored in its record (docs/design.md#closed-loop).

Round 0 is the record itself (its prompt, answer, scores and execution are the open-loop
ones); each replan is a :class:`RoundRecord`; :class:`LoopOutcome` sums the episode up.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from vlm_bench.types.base import FiniteFrozen
from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.execution import ExecutionSummary, FailureCode
from vlm_bench.types.parse import ParseResult

LoopEnd = Literal["success", "max_rounds", "budget", "no_plan", "executor_crash"]
"""Why a closed-loop episode ended: the task succeeded, K replans were used, the step budget
ran out, a round's answer held no plan to execute (the oracle's replans, a parse failure, an
empty plan), or the executor raised."""


def round_request_id(key: str, round_index: int) -> str:
    """The request id of an episode's round: the episode key for round 0 (as in an open
    loop), ``key#r<round>`` for a replan."""
    return key if round_index == 0 else f"{key}#r{round_index}"


class RoundRecord(FiniteFrozen):
    """One replan of a closed-loop episode: what the model was told, answered and did."""

    round: int = Field(ge=1, description="The round (1 = first replan).")
    prompt_hash: str = Field(description="Hash of the replan's prompt (its cache key).")
    feedback: Feedback = Field(description="What the prompt told the model.")
    raw_output: str = Field(default="", description="The model's text, verbatim.")
    parse: ParseResult | None = Field(default=None, description="Parser result.")
    plan: list[dict[str, Any]] | None = Field(
        default=None, description="Valid steps executed, in the paper's JSON format."
    )
    truncated: int = Field(default=0, ge=0, description="Steps cut off by the step budget.")
    execution: ExecutionSummary | None = Field(
        default=None, description="The round's execution (None: nothing executed)."
    )
    latency_s: float = Field(default=0.0, ge=0, description="Backend time of the answer (s).")
    prompt_tokens: int | None = Field(default=None, description="Prompt tokens, if known.")
    completion_tokens: int | None = Field(default=None, description="Generated tokens.")
    finish_reason: str | None = Field(default=None, description="Why generation stopped.")
    cached: bool = Field(default=False, description="The answer came from the cache.")


class LoopOutcome(FiniteFrozen):
    """A closed-loop episode summed up."""

    succ_at: tuple[bool, ...] = Field(
        description="succ_at[k]: the task succeeded within rounds 0..k (k = 0..K)."
    )
    rounds_used: int = Field(ge=1, description="Rounds that got an answer (round 0 included).")
    recovered: bool = Field(description="Failed in round 0, succeeded in a later round.")
    failure_codes: tuple[str | None, ...] = Field(
        description="Each round's failure code (None: that round succeeded or ran nothing)."
    )
    steps_executed: int = Field(ge=0, description="Steps run (ok or failed), all rounds.")
    budget: int = Field(ge=1, description="The episode's step budget.")
    end: LoopEnd = Field(description="Why the episode ended.")


class StepFailure(FiniteFrozen):
    """The step that failed in a round, as the executor typed it (never read back from text)."""

    index: int = Field(ge=0, description="The step's index in its round's plan.")
    code: FailureCode = Field(description="The kind of failure.")
    detail: str = Field(description="One-line failure detail (no step prefix).")


class RoundOutcome(FiniteFrozen):
    """What a round's execution tells the round machine."""

    execution: ExecutionSummary = Field(description="The round's execution, as recorded.")
    failed_step: StepFailure | None = Field(
        default=None, description="The step that failed (None: every step ran, or a crash)."
    )
    held: str | None = Field(default=None, description="What the gripper holds after it.")
    crashed: bool = Field(default=False, description="The executor raised.")
