"""Recompute scores (and executions) from stored model answers (no model calls), and score a
single output."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError
from vlm_bench.runner.evaluate import EpisodeInfo, evaluate_output, scored_record
from vlm_bench.runner.execution_pools import make_pool
from vlm_bench.runner.executions import Executions
from vlm_bench.runner.progress import progress_bar
from vlm_bench.sim.visibility import first_target_visible
from vlm_bench.storage import RunStore
from vlm_bench.types.benchmark_version import require_current_version
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.records import CachedResponse, EpisodeRecord, OutputScore, usage_of
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
    """Records whose parse, plan, scores, tags or execution changed."""
    executed: int = 0
    """Plans executed again (runs that execute plans)."""
    torn_bytes: int = 0
    """Bytes of a torn last record line (a crash mid-write) cut off the records file."""


def _response(store: RunStore, record: EpisodeRecord) -> CachedResponse:
    """The cached answer of a record; the record's own copy of the text if the cache lacks it."""
    cached = store.cached_response(record.key, record.prompt_hash)
    if cached is not None:
        return cached
    return CachedResponse(
        key=record.key,
        prompt_hash=record.prompt_hash,
        text=record.raw_output,
        **usage_of(record),
    )


def rescore_run(
    run_dir: Path, *, progress: bool = False, execution: ExecutionOptions | None = None
) -> RescoreOutcome:
    """Re-parse and re-score every answered episode of a run with the current code.

    Uses the run's own scoring configuration and the response cache; error records are kept
    as they are (a resume retries them). When the run executes plans, every plan is executed
    again with the run's ``uav_noise``, in the pool ``execution`` asks for (default: one worker
    process per core; identical plans on one episode run once). ``records.jsonl`` is rewritten
    atomically, one line per episode in the order it had, keeping each record's timing and
    token counts. A torn last line (a crash mid-write) is cut off and counted in
    :attr:`RescoreOutcome.torn_bytes`: its episode has no record until the run resumes.

    Args:
        run_dir: The run folder.
        progress: Show a progress bar on stderr.
        execution: Where plans are executed.

    Raises:
        NotARunError: ``run_dir`` has no manifest.
        RunLockedError: A run is writing the folder.
        BenchmarkVersionError: The run evaluated another benchmark version (its answers
            belong to other episodes or prompts).
    """
    with RunStore.open_existing(run_dir) as store:
        config = store.manifest.config
        require_current_version(config.benchmark_version, f"run {store.paths.root}")
        if config.loop == "closed":
            raise ConfigError(
                "rescore covers open-loop runs; re-run a closed-loop run with the same "
                "command (its answers come from the response cache, round by round)"
            )
        episodes: dict[tuple[str, int], Episode] = {}
        label = f"rescore {store.paths.run_id}"
        records = list(store.records.values())
        done: dict[str, EpisodeRecord] = {}
        options = execution or ExecutionOptions()
        executions = (
            Executions(make_pool(options), config.executor_config(), stall_s=options.stall_s)
            if config.execute
            else None
        )
        try:
            with progress_bar(len(records), label, enabled=progress) as advance:
                for record in records:
                    new = record
                    if record.ok:
                        ep_key = (record.task_id, record.seed)
                        if ep_key not in episodes:
                            episodes[ep_key] = get_episode(record.task_id, record.seed)
                        new = _rescored(store, record, episodes[ep_key], config.scoring)
                        if executions is not None:
                            finished = executions.submit(episodes[ep_key], new)
                            if finished is None:
                                continue
                            new = finished
                    done[record.key] = new
                    advance(1)
                for new in executions.drain() if executions is not None else ():
                    done[new.key] = new
                    advance(1)
        finally:
            if executions is not None:
                executions.close()
        out = [done[record.key] for record in records]
        pairs = zip(out, records, strict=True)
        changed = sum(new.without_timing() != old.without_timing() for new, old in pairs)
        store.rewrite_records(out)
        executed = executions.stats.executed if executions is not None else 0
        return RescoreOutcome(
            store.paths.root,
            store.manifest,
            tuple(out),
            changed,
            executed,
            store.torn_record_bytes,
        )


def _rescored(
    store: RunStore, record: EpisodeRecord, episode: Episode, scoring: ScoringConfig
) -> EpisodeRecord:
    """The record recomputed from its cached answer (its execution is executed separately)."""
    info = EpisodeInfo(
        record.run_id,
        record.key,
        record.variant,
        record.model,
        record.prompt_hash,
        object_order=record.object_order,
        first_target_visible=first_target_visible(episode),
    )
    new = scored_record(info, episode, _response(store, record), scoring, cached=record.cached)
    return new.model_copy(update={"created": record.created})


def score_output(
    task_id: str,
    seed: int,
    text: str,
    variant: InstructionVariant = "explicit",
    scoring: ScoringConfig | None = None,
) -> OutputScore:
    """Score one raw model output against an episode's GT (the ``score`` command)."""
    episode = get_episode(task_id, seed)
    ev = evaluate_output(text, episode, scoring or ScoringConfig())
    return OutputScore(
        task_id=episode.task_id,
        seed=episode.seed,
        instruction=variant,
        parse=ev.parse,
        plan=ev.plan,
        gt_plan=plan_to_json(episode.gt_plan),
        scores=ev.scores,
        error_tags=ev.error_tags,
    )
