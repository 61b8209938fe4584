"""The episode pipeline: episode → snapshots → prompt → backend (batched) → parse → score →
execute → record.

Bad model output is scored (and its valid plan executed when the run executes plans), a failed
generation is recorded as an ``error`` record (a resume retries it), and every record is durable
as soon as it is written. Plans execute off the generation path
(:mod:`vlm_bench.runner.executions`): while worker processes execute one batch's plans the backend
generates the next, and each record is written once, with its execution, when its execution
finishes. Answers are cached before their records, keyed by episode and prompt hash, so an
interrupt (Ctrl-C, or a kill) loses only executions: a resume scores the cached answers again
and re-executes what has no record.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

from vlm_bench.backends import Backend
from vlm_bench.episodes import get_episode
from vlm_bench.errors import VlmBenchError
from vlm_bench.parsing import parse_plan
from vlm_bench.rounds.replan_prompt import replan_generation_request
from vlm_bench.rounds.state import ReplanRequest
from vlm_bench.runner.cached_snapshots import SnapshotSource
from vlm_bench.runner.episode_request import episode_request
from vlm_bench.runner.evaluate import EpisodeInfo, error_record, scored_record
from vlm_bench.runner.executions import Ask, Executions
from vlm_bench.runner.interrupt import StopFlag
from vlm_bench.runner.progress import RunProgress
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.sim.visibility import first_target_visible
from vlm_bench.storage import RunStore
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import GenerationRequest, GenerationResult
from vlm_bench.types.parse import ParseResult
from vlm_bench.types.records import CachedResponse, EpisodeRecord, usage_of
from vlm_bench.types.run import RunConfig

STOP_POLL_S = 0.2
"""Longest wait for an execution before the stop flag (Ctrl-C, SIGTERM) is read again (s)."""


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
    changed: int = 0
    """Records whose parse, plan, scores, tags or execution changed (rescore)."""
    torn_bytes: int = 0
    """Bytes of a torn last record line cut off when the folder was opened (rescore)."""


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
        progress: RunProgress | None = None,
        stop: StopFlag | None = None,
        executions: Executions | None = None,
        sees_images: bool = True,
    ) -> None:
        """Set up the pipeline of one run.

        Args:
            config: The run configuration.
            store: The open run folder.
            backend: Returns the backend; called only when a model answer is needed, so a
                resume of a finished run never loads the model.
            snapshots: Source of snapshot PNGs.
            progress: Shows generation and execution as they go.
            stop: Checked between batches and executions; a requested stop raises
                ``KeyboardInterrupt`` after the finished episodes are written (executions in
                flight are dropped: a resume runs them again).
            executions: Where episodes execute, when the run executes plans (the pipeline
                closes it): the replans it asks for are generated here; None = the run does
                not execute plans.
            sees_images: The backend reads images; False: no views are rendered and its
                requests carry none (prompt hashes and records are the same either way).
        """
        self.config = config
        self.store = store
        self._backend = backend
        self.snapshots = snapshots
        self.sees_images = sees_images
        self.progress = progress or RunProgress(0, enabled=False)
        self.stats = PipelineStats()
        self._episode: Episode | None = None
        self.stop = stop or StopFlag()
        self.executions = executions if config.execute else None

    def run(self, refs: Sequence[EpisodeRef]) -> PipelineStats:
        """Evaluate every episode of ``refs`` that has no ok record yet."""
        pending = [r for r in refs if not self.store.is_done(r.key)]
        self.stats.total = len(refs)
        self.stats.skipped = len(refs) - len(pending)
        self.progress.skipped(self.stats.skipped)
        try:
            for batch in _chunks(pending, self.config.generation.batch_size):
                self.stop.check()
                self._run_batch([self._prepare(ref) for ref in batch])
                self._write_executed(block=False)
                self._run_replans()
            while self.executions is not None and self.executions.in_flight:
                self.stop.check()
                self._write_executed(block=True)  # waits at most STOP_POLL_S
                self._run_replans()
        except BaseException:
            if self.executions is not None:
                self.executions.close(cancel=True)
            raise
        if self.executions is not None:
            self.executions.close()
        return self.stats

    def _write_executed(self, block: bool) -> None:
        """Write the records whose executions finished (``block``: wait up to
        :data:`STOP_POLL_S` for one)."""
        if self.executions is None:
            return
        for record in self.executions.collect(block=block, timeout=STOP_POLL_S):
            self._write(record)
        r = self.executions.stats
        self.stats.executed = r.executed
        self.stats.exec_crashes = r.crashes
        self.stats.exec_crash_messages = list(r.crash_messages)

    def _run_replans(self) -> None:
        """Generate the replans episodes wait for (answers cached first, keyed by each round's
        prompt hash and the conversation before it) and send them on; a failed generation
        writes the episode's error record (a resume runs it again)."""
        executions = self.executions
        if executions is None:
            return
        asks = [self._ask(executions, key, replan) for key, replan in executions.requests()]
        for start in range(0, len(asks), self.config.generation.batch_size):
            self.stop.check()
            chunk = asks[start : start + self.config.generation.batch_size]
            misses = [a for a in chunk if self.store.cached_response(a.key, a.prompt_hash) is None]
            results = self._generate([a.request for a in misses])
            for ask in chunk:
                record = self._answer(executions, ask, results)
                if record is not None:
                    self._write(record)

    def _ask(self, executions: Executions, key: str, replan: ReplanRequest) -> Ask:
        episode = executions.episode(key)
        request, prompt_hash = replan_generation_request(
            key,
            episode,
            replan,
            self.config.prompt_config(executions.variant(key)),
            executions.conversation(key),
            constrained=self.config.generation.constrained,
            show_images=bool(executions.view.views),
        )
        return Ask(key, prompt_hash, request)

    def _answer(
        self, executions: Executions, ask: Ask, results: dict[str, GenerationResult]
    ) -> EpisodeRecord | None:
        cached = self.store.cached_response(ask.key, ask.prompt_hash)
        if cached is not None:
            self.stats.cached += 1
            return executions.answer(ask, cached, self._parse(executions, ask, cached), True)
        result = results[ask.request.id]
        if result.error is not None:
            self.stats.errors += 1
            if len(self.stats.error_messages) < 5:
                self.stats.error_messages.append(f"{ask.request.id}: {result.error}")
            return executions.fail(ask, result.error, result.latency_s)
        response = CachedResponse(
            key=ask.key,
            prompt_hash=ask.prompt_hash,
            text=result.text,
            **usage_of(result),
        )
        self.store.append_response(response)
        return executions.answer(ask, response, self._parse(executions, ask, response), False)

    @staticmethod
    def _parse(executions: Executions, ask: Ask, response: CachedResponse) -> ParseResult:
        return parse_plan(response.text, executions.episode(ask.key).object_ids())

    def _write(self, record: EpisodeRecord) -> None:
        self.store.append_record(record)
        self.progress.written(1)

    def _episode_of(self, ref: EpisodeRef) -> Episode:
        ep = self._episode
        if ep is None or ep.task_id != ref.task_id or ep.seed != ref.seed:
            ep = self._episode = get_episode(ref.task_id, ref.seed)
        return ep

    def _prepare(self, ref: EpisodeRef) -> _Prepared:
        episode = self._episode_of(ref)
        images = self.snapshots.images(episode) if self.sees_images else None
        prompt, request = episode_request(self.config, ref, episode, images)
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
                        **usage_of(result),
                    )
                    store.append_response(response)
                    record = scored_record(p.info, p.episode, response, self.config.scoring)
                else:
                    record = error_record(p.info, p.episode, result.error, result.latency_s)
                    self.stats.errors += 1
                    if len(self.stats.error_messages) < 5:
                        self.stats.error_messages.append(f"{p.ref.key}: {result.error}")
            self.progress.generated(1)
            if record.ok:
                self.stats.scored += 1
                if self.executions is not None:
                    self.stop.check()
                    finished = self.executions.submit(p.episode, record, p.request)
                    if finished is None:
                        continue  # written when its execution finishes
                    record = finished
            self._write(record)
