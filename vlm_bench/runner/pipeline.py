"""The episode pipeline: episode → snapshots → prompt → backend (batched) → parse → score →
execute → record.

Bad model output is scored (and its valid plan executed when the run executes plans), a failed
generation is recorded as an ``error`` record (a resume retries it), and every record is durable
as soon as it is written: an interrupt loses at most the batch in flight (a requested stop is
also honoured before each execution). Answers are cached before their records, keyed by episode
and prompt hash, so a batch whose answers arrived is never asked again.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

from vlm_bench.backends import Backend
from vlm_bench.episodes import make_episode
from vlm_bench.errors import VlmBenchError
from vlm_bench.parsing import plan_json_schema
from vlm_bench.prompting import build_prompt
from vlm_bench.runner.evaluate import EpisodeInfo, error_record, scored_record
from vlm_bench.runner.execution import PlanExecutor
from vlm_bench.runner.interrupt import StopFlag
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.runner.snapshots import SnapshotSource
from vlm_bench.sim.visibility import first_target_visible
from vlm_bench.storage import RunStore
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import GenerationRequest, GenerationResult, RequestMeta
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.run import RunConfig


@dataclass
class PipelineStats:
    """Counts of one pipeline pass."""

    total: int = 0
    """Episodes selected."""
    skipped: int = 0
    """Already finished in the folder (resume)."""
    scored: int = 0
    """Records written with status ok."""
    errors: int = 0
    """Records written with status error (backend failures)."""
    cached: int = 0
    """Answers taken from the response cache instead of the model."""
    generate_calls: int = 0
    """``Backend.generate`` calls made."""
    error_messages: list[str] = field(default_factory=list)
    """The first few backend error messages."""
    executed: int = 0
    """Plans executed in the simulator."""
    exec_crashes: int = 0
    """Executions that ended in an executor exception (recorded as failures)."""
    exec_crash_messages: list[str] = field(default_factory=list)
    """The first few executor exception messages."""


@dataclass(frozen=True)
class _Prepared:
    ref: EpisodeRef
    episode: Episode
    info: EpisodeInfo
    request: GenerationRequest


def _chunks(items: Sequence[EpisodeRef], size: int) -> Iterator[Sequence[EpisodeRef]]:
    for start in range(0, len(items), size):
        yield items[start : start + size]


class EpisodePipeline:
    """Runs a run's pending episodes through one backend into one store."""

    def __init__(
        self,
        config: RunConfig,
        store: RunStore,
        backend: Callable[[], Backend],
        snapshots: SnapshotSource,
        advance: Callable[[int], None] | None = None,
        stop: StopFlag | None = None,
    ) -> None:
        """Set up the pipeline of one run.

        Args:
            config: The run configuration.
            store: The open run folder.
            backend: Returns the backend; called only when a model answer is needed, so a
                resume of a finished run never loads the model.
            snapshots: Source of snapshot PNGs.
            advance: Progress callback, called with the number of episodes finished.
            stop: Checked between batches; a requested stop raises ``KeyboardInterrupt``
                after the finished episodes are written.
        """
        self.config = config
        self.store = store
        self._backend = backend
        self.snapshots = snapshots
        self.advance = advance or (lambda n: None)
        self.stats = PipelineStats()
        self._episode: Episode | None = None
        self.stop = stop or StopFlag()
        self.executor = PlanExecutor(config.uav_noise) if config.execute else None

    def run(self, refs: Sequence[EpisodeRef]) -> PipelineStats:
        """Evaluate every episode of ``refs`` that has no ok record yet."""
        pending = [r for r in refs if not self.store.is_done(r.key)]
        self.stats.total = len(refs)
        self.stats.skipped = len(refs) - len(pending)
        self.advance(self.stats.skipped)
        for batch in _chunks(pending, self.config.generation.batch_size):
            self.stop.check()
            self._run_batch([self._prepare(ref) for ref in batch])
        return self.stats

    def _execute(self, episode: Episode, record: EpisodeRecord) -> EpisodeRecord:
        """Attach the execution of the record's plan when the run executes plans."""
        if self.executor is None:
            return record
        self.stop.check()  # an execution takes seconds: honour a stop before starting one
        record = self.executor.execute(episode, record)
        stats = self.stats
        stats.executed = self.executor.executed
        stats.exec_crashes = self.executor.crashes
        stats.exec_crash_messages = list(self.executor.crash_messages)
        return record

    def _episode_of(self, ref: EpisodeRef) -> Episode:
        ep = self._episode
        if ep is None or ep.task_id != ref.task_id or ep.seed != ref.seed:
            ep = self._episode = make_episode(ref.task_id, ref.seed)
        return ep

    def _prepare(self, ref: EpisodeRef) -> _Prepared:
        episode = self._episode_of(ref)
        prompt = build_prompt(
            episode, self.snapshots.images(episode), self.config.prompt_config(ref.variant)
        )
        object_ids = episode.object_ids()
        request = prompt.to_request(
            ref.key,
            episode_id=ref.key,
            meta=RequestMeta(
                task_id=ref.task_id,
                seed=ref.seed,
                gt_plan=episode.gt_plan,
                arm_steps=tuple(episode.arm_steps()),
                object_ids=tuple(object_ids),
            ),
            json_schema=plan_json_schema(object_ids)
            if self.config.generation.constrained
            else None,
        )
        info = EpisodeInfo(
            self.store.paths.run_id,
            ref.key,
            ref.variant,
            self.config.model,
            prompt.prompt_hash,
            object_order=prompt.object_order,
            first_target_visible=first_target_visible(episode),
        )
        return _Prepared(ref, episode, info, request)

    def _generate(self, requests: list[GenerationRequest]) -> dict[str, GenerationResult]:
        if not requests:
            return {}
        backend = self._backend()
        self.stats.generate_calls += 1
        try:
            results = backend.generate(requests, self.config.generation)
        except VlmBenchError:
            raise  # configuration errors stop the run with their one-line message
        except Exception as exc:  # noqa: BLE001  (a backend bug must not kill a long run)
            message = f"backend raised {type(exc).__name__}: {exc}"
            results = [GenerationResult(id=r.id, error=message) for r in requests]
        by_id = {r.id: r for r in results}
        return {
            req.id: by_id.get(req.id)
            or GenerationResult(id=req.id, error="backend returned no result for this request")
            for req in requests
        }

    def _run_batch(self, batch: list[_Prepared]) -> None:
        store = self.store
        misses = [p for p in batch if store.cached_response(p.ref.key, p.info.prompt_hash) is None]
        results = self._generate([p.request for p in misses])
        for p in batch:
            cached = store.cached_response(p.ref.key, p.info.prompt_hash)
            if cached is not None:
                self.stats.cached += 1
                record = scored_record(p.info, p.episode, cached, self.config.scoring, cached=True)
            else:
                result = results[p.request.id]
                if result.error is None:
                    response = CachedResponse(
                        key=p.ref.key,
                        prompt_hash=p.info.prompt_hash,
                        text=result.text,
                        latency_s=result.latency_s,
                        prompt_tokens=result.prompt_tokens,
                        completion_tokens=result.completion_tokens,
                        finish_reason=result.finish_reason,
                    )
                    store.append_response(response)
                    record = scored_record(p.info, p.episode, response, self.config.scoring)
                else:
                    record = error_record(p.info, p.episode, result.error, result.latency_s)
                    self.stats.errors += 1
                    if len(self.stats.error_messages) < 5:
                        self.stats.error_messages.append(f"{p.ref.key}: {result.error}")
            if record.ok:
                record = self._execute(p.episode, record)
                self.stats.scored += 1
            store.append_record(record)
            self.advance(1)
