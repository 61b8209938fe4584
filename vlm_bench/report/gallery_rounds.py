"""A closed-loop episode's replans in the gallery: per round, the views of the state the round
started from (the failure), the feedback the model got, its new plan and the outcome.

The records keep no images of later rounds; the views are rendered again by executing the
episode's earlier rounds (the simulation is deterministic, so these are the pixels the model
saw), which needs MuJoCo and is skipped when the gallery may not render.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field

from vlm_bench.report.gallery_views import to_jpeg
from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunManifest


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
    manifest: RunManifest,
    url: Callable[[int, str, bytes], str],
) -> None:
    """Render each replan's views by executing the rounds before it (module doc); ``url``
    turns (round, view, JPEG bytes) into the image's URL."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.parsing import parse_plan
    from vlm_bench.runner.loop_jobs import LoopJob, StateRequest, replay_rounds
    from vlm_bench.runner.plan_executor import record_plan

    config = manifest.config
    first = record_plan(record)
    if not cards or first is None or record.rounds is None:
        return
    plans = [tuple(first)]
    ids = get_episode(record.task_id, record.seed).object_ids()
    for row in record.rounds:
        steps = parse_plan(row.raw_output, ids).valid_steps() if row.parse is not None else []
        plans.append(tuple(steps[: len(row.plan or ())]))
    state = StateRequest(VIEWS, config.resolution, config.labels)
    for card in cards:
        rounds = tuple(plans[: card.round])
        job = LoopJob(record.task_id, record.seed, config.executor_config(), rounds, state)
        shown = replay_rounds(job).state
        if shown is not None:
            card.views = {v: url(card.round, v, to_jpeg(png)) for v, png in shown.images.items()}
