"""Recompute scores from stored model answers (no model calls), and score a single output."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vlm_bench.episodes import make_episode
from vlm_bench.runner.evaluate import EpisodeInfo, evaluate_output, scored_record
from vlm_bench.storage import RunStore
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.run import RunManifest
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.task import InstructionVariant


@dataclass(frozen=True)
class RescoreOutcome:
    """The rewritten records of a rescored run."""

    run_dir: Path
    manifest: RunManifest
    records: tuple[EpisodeRecord, ...]
    changed: int
    """Records whose parse, plan, scores or tags changed."""


def _response(store: RunStore, record: EpisodeRecord) -> CachedResponse:
    """The cached answer of a record; the record's own copy of the text if the cache lacks it."""
    cached = store.cached_response(record.key, record.prompt_hash)
    if cached is not None:
        return cached
    return CachedResponse(
        key=record.key, prompt_hash=record.prompt_hash, text=record.raw_output,
        latency_s=record.latency_s, prompt_tokens=record.prompt_tokens,
        completion_tokens=record.completion_tokens, finish_reason=record.finish_reason,
    )


def rescore_run(run_dir: Path) -> RescoreOutcome:
    """Re-parse and re-score every answered episode of a run with the current code.

    Uses the run's own scoring configuration and the response cache; error records are kept
    as they are (a resume retries them). ``records.jsonl`` is rewritten atomically, one line per
    episode, keeping each record's timing and token counts.

    Raises:
        NotARunError: ``run_dir`` has no manifest.
        RunLockedError: A run is writing the folder.
    """
    with RunStore.open_existing(run_dir) as store:
        scoring = store.manifest.config.scoring
        episodes: dict[tuple[str, int], Episode] = {}
        out: list[EpisodeRecord] = []
        changed = 0
        for record in store.records.values():
            if not record.ok:
                out.append(record)
                continue
            ep_key = (record.task_id, record.seed)
            if ep_key not in episodes:
                episodes[ep_key] = make_episode(record.task_id, record.seed)
            info = EpisodeInfo(record.run_id, record.key, record.variant, record.model,
                               record.prompt_hash)
            new = scored_record(info, episodes[ep_key], _response(store, record), scoring,
                                cached=record.cached)
            new = new.model_copy(update={"created": record.created})
            changed += new.without_timing() != record.without_timing()
            out.append(new)
        store.rewrite_records(out)
        return RescoreOutcome(store.paths.root, store.manifest, tuple(out), changed)


def score_output(
    task_id: str, seed: int, text: str, variant: InstructionVariant = "explicit",
    scoring: ScoringConfig | None = None,
) -> dict[str, Any]:
    """Score one raw model output against an episode's GT (the ``score`` command).

    Returns:
        JSON-ready dict: ``task_id, seed, instruction, parse, plan, gt_plan, scores,
        error_tags``.
    """
    episode = make_episode(task_id, seed)
    ev = evaluate_output(text, episode, scoring or ScoringConfig())
    return {
        "task_id": episode.task_id,
        "seed": episode.seed,
        "instruction": variant,
        "parse": ev.parse.model_dump(mode="json"),
        "plan": ev.plan,
        "gt_plan": plan_to_json(episode.gt_plan),
        "scores": ev.scores.model_dump(mode="json"),
        "error_tags": list(ev.error_tags),
    }
