"""The pieces of a closed-loop episode's rounds: the feedback on the steps a round ran, the
conversation a replan carries, its cache key, and the episode's outcome."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence

from vlm_bench.types.closed_loop import ExecutedStep, HistoryMode
from vlm_bench.types.execution import ExecutionSummary
from vlm_bench.types.generation import GenerationRequest, ImagePart, TextPart, Turn
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.rounds import LoopEnd, LoopOutcome

Turns = list[tuple[GenerationRequest | None, str, str]]
"""Each answered round: its request (None where not given), the answer, its cache key."""


def ran_steps(plan: Sequence[UavStep | ArmStep], summary: ExecutionSummary) -> list[ExecutedStep]:
    """The steps of ``plan`` that ran: the done ones, then the failed one (if a step failed)."""
    done = [ExecutedStep(step=s, status="done") for s in plan[: summary.n_steps_done]]
    if summary.steps_ok or summary.n_steps_done >= len(plan):
        return done
    detail = summary.failure_reason or ""
    if detail.startswith("step ") and ": " in detail:
        detail = detail.split(": ", 1)[1]
    code = str(summary.failure_code) if summary.failure_code is not None else None
    failed = ExecutedStep(
        step=plan[summary.n_steps_done], status="failed", code=code, detail=detail
    )
    return [*done, failed]


def kept_request(
    request: GenerationRequest | None, history: HistoryMode
) -> GenerationRequest | None:
    """What a later round's conversation needs of ``request``: its user turn, each image
    replaced by a note unless ``history`` is ``images`` (only the current views are shown)."""
    if request is None:
        return None
    user = tuple(
        TextPart(text=f"[{p.view} view of that moment, not shown again]")
        if isinstance(p, ImagePart) and history == "text"
        else p
        for p in request.user
    )
    return request.model_copy(update={"user": user, "history": ()})


def history_turns(turns: Turns) -> tuple[Turn, ...]:
    """The earlier rounds as turns: each request's user turn and the model's answer."""
    out: list[Turn] = []
    for request, answer, _ in turns:
        if request is not None:
            out.append(Turn(role="user", content=request.user))
        out.append(Turn(role="assistant", content=(TextPart(text=answer),)))
    return tuple(out)


def chain_hash(prompt_hash: str, turns: Turns, history: HistoryMode) -> str:
    """A replan's cache key: its prompt, the conversation before it (every earlier round's
    key and answer) and how that conversation is shown."""
    digest = hashlib.sha256(f"{prompt_hash}|history={history}".encode())
    for _, answer, key in turns:
        digest.update(f"|{key}|".encode() + hashlib.sha256(answer.encode()).digest())
    return digest.hexdigest()


def loop_outcome(
    executions: Sequence[ExecutionSummary | None],
    end: LoopEnd,
    max_rounds: int,
    steps_executed: int,
    budget: int,
) -> LoopOutcome:
    """A closed-loop episode summed up from each round's execution (None: nothing ran)."""
    won = next((i for i, e in enumerate(executions) if e is not None and e.exec_success), None)
    return LoopOutcome(
        succ_at=tuple(won is not None and won <= k for k in range(max_rounds + 1)),
        rounds_used=len(executions),
        recovered=won is not None and won > 0,
        failure_codes=tuple(
            "no_plan" if e is None else (str(e.failure_code) if e.failure_code else None)
            for e in executions
        ),
        steps_executed=steps_executed,
        budget=budget,
        end=end,
    )
