"""A closed-loop episode's replans in the gallery: per round, the views of the state the round
started from (the failure), the feedback the model got, its new plan and the outcome.

The records keep no images of later rounds; the views come from the gallery's view source
(:mod:`vlm_bench.report.gallery_views`), which renders them again by executing the episode's
earlier rounds, or shows none.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field

from vlm_bench.report.gallery_views import ViewSource, to_jpeg
from vlm_bench.types.records import EpisodeRecord


@dataclass
class RoundCard:
    """What the gallery shows of one replan."""

    round: int
    feedback: list[str]
    """One line per step run before it, then what was held."""
    plan: list[str]
    """The executed steps, one JSON object per line."""
    outcome: str
    """``success``, ``failed`` or ``not_executed``."""
    failure: str | None
    perturbations: list[str]
    views: dict[str, str] = field(default_factory=dict)
    """View → image URL of the state the round started from."""


def _feedback(record: EpisodeRecord, index: int) -> list[str]:
    assert record.rounds is not None
    fb = record.rounds[index].feedback
    lines = [
        f"{json.dumps({k: v for k, v in s.step.model_dump(mode='json').items() if v is not None})}"
        f": {s.status}" + (f" ({s.code}): {s.detail}" if s.status == "failed" else "")
        for s in fb.executed
    ]
    if fb.incomplete:
        lines.append("every step succeeded, but the task is not complete")
    lines.append(f"holding: {fb.held or 'nothing'}")
    return lines


def round_cards(record: EpisodeRecord) -> list[RoundCard]:
    """The replans of ``record`` (none for an open-loop record), without views."""
    out = []
    for i, row in enumerate(record.rounds or ()):
        execution = row.execution
        out.append(
            RoundCard(
                round=row.round,
                feedback=_feedback(record, i),
                plan=[json.dumps(step) for step in row.plan or ()],
                outcome="not_executed"
                if execution is None
                else ("success" if execution.exec_success else "failed"),
                failure=None if execution is None else execution.failure_reason,
                perturbations=[
                    f"{e.kind} {e.object} (step {e.step})"
                    for e in (execution.perturbations if execution is not None else None) or ()
                ],
            )
        )
    return out


def attach_round_views(
    record: EpisodeRecord,
    cards: list[RoundCard],
    source: ViewSource,
    url: Callable[[int, str, bytes], str],
) -> None:
    """Each replan's views from ``source``; ``url`` turns (round, view, JPEG bytes) into the
    image's URL."""
    for card in cards:
        shown = source.round_views(record, card.round)
        card.views = {v: url(card.round, v, to_jpeg(png)) for v, png in shown.items()}
