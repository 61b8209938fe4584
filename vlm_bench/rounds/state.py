"""What a driver hands the round machine and the planner after a round: the round's typed
outcome, and the state it left (the episode as it stands, what is held, the views)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, ExecutionSummary
from vlm_bench.types.rounds import RoundOutcome, StepFailure

if TYPE_CHECKING:
    from vlm_bench.executor.live_episode import LiveEpisode


@dataclass(frozen=True)
class StateView:
    """How to show the state a failed round left."""

    views: tuple[str, ...] = ()
    """The views to render (none for a planner that reads no images)."""
    size: int = 448
    """View side (px)."""
    labels: bool = True
    """Draw the set-of-marks labels."""


@dataclass(frozen=True)
class RoundState:
    """The state a failed round left."""

    now: Episode
    """The episode as it stands (objects, drawers, the UAV where they are)."""
    held: str | None
    """What the gripper holds."""
    images: dict[str, bytes]
    """PNG views of the state, by view name."""
    digest: str
    """The simulator state's digest (:func:`~vlm_bench.executor.live_state.state_digest`)."""


@dataclass(frozen=True)
class ReplanRequest:
    """A replan to answer: what the machine tells the planner and the state it plans from."""

    feedback: Feedback
    state: RoundState

    @property
    def round(self) -> int:
        """The round the answer executes as (1 = first replan)."""
        return self.feedback.round


def round_outcome(
    result: ExecutionResult, held: str | None, summary: ExecutionSummary | None = None
) -> RoundOutcome:
    """The typed outcome of an execution (``summary``: its stored summary, if made already)."""
    failed = next((o for o in result.steps if o.status == "failed"), None)
    failure = None
    if failed is not None and failed.failure_code is not None:
        failure = StepFailure(
            index=failed.index, code=failed.failure_code, detail=failed.reason or ""
        )
    return RoundOutcome(
        execution=summary or ExecutionSummary.of(result), failed_step=failure, held=held
    )


def describe_state(live: LiveEpisode, view: StateView) -> RoundState:
    """The state ``live`` is in now, with ``view``'s views rendered."""
    from vlm_bench.executor.live_state import episode_now, render_now, state_digest

    digest = state_digest(live)
    now = episode_now(live)
    images = render_now(live, now, view.views, view.size, view.labels)
    return RoundState(now, live.held, images, digest)
