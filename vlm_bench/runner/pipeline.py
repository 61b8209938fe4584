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

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from vlm_bench.episodes import get_episode
from vlm_bench.rounds.replan_prompt import replan_generation_request
from vlm_bench.runner.answers import Answer, ModelAnswers, Question
from vlm_bench.runner.cached_snapshots import SnapshotSource
from vlm_bench.runner.episode_request import prompt_request
from vlm_bench.runner.evaluate import EpisodeInfo, answered_record
from vlm_bench.runner.execution_pools import ExecutionPool
from vlm_bench.runner.executions import Executions, ReplanAsk
from vlm_bench.runner.interrupt import StopFlag
from vlm_bench.runner.progress import RunProgress
from vlm_bench.runner.run_plan import RunPlan
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.sim.visibility import first_target_visible
from vlm_bench.storage import RunStore
from vlm_bench.types.episode import Episode
from vlm_bench.types.records import EpisodeRecord

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
    episode: Episode
    info: EpisodeInfo
    question: Question


def _chunks(items: Sequence[EpisodeRef], size: int) -> Iterator[Sequence[EpisodeRef]]:
    for start in range(0, len(items), size):
        yield items[start : start + size]


class EpisodePipeline:
    """Runs a run's pending episodes through the model's answers into one store.

    Args:
        plan: The run's plan (its episodes, prompt options, decoding, scoring).
        store: The open run folder.
        answers: The model's answers through the run's response cache (round 0's and the
            replans').
        snapshots: Source of snapshot PNGs (the views the plan shows).
        progress: Shows generation and execution as they go.
        stop: Checked between batches and executions; a requested stop raises
            ``KeyboardInterrupt`` after the finished episodes are written (executions in
            flight are dropped: a resume runs them again).
        pool: Where the plan's episodes execute, when the run executes plans (the pipeline's
            :class:`Executions` drives it and closes it); None = the run executes no plans.
        stall_s: Longest time with executions in flight and none finishing (s).
    """

    def __init__(
        self,
        plan: RunPlan,
        store: RunStore,
        answers: ModelAnswers,
        snapshots: SnapshotSource,
        progress: RunProgress | None = None,
        stop: StopFlag | None = None,
        pool: ExecutionPool | None = None,
        stall_s: float | None = None,
    ) -> None:
        self.plan = plan
        self.store = store
        self.answers = answers
        self.snapshots = snapshots
        self.progress = progress or RunProgress(0, enabled=False)
        self.stats = PipelineStats()
        self.stop = stop or StopFlag()
        self.executions: Executions | None = None
        if pool is not None and plan.executor is not None:
            self.executions = Executions(
                pool,
                plan.executor,
                plan.loop,
                shown=plan.shown,
                history=plan.history,
                ask_model=self.ask_model,
                on_change=self.progress.executions_changed,
                stall_s=stall_s,
            )
        self._episode: Episode | None = None

    def run(self) -> PipelineStats:
        """Evaluate every episode of the plan that has no ok record yet; each record is written
        as its episode ends."""
        refs = self.plan.episodes
        pending = [r for r in refs if not self.store.is_done(r.key)]
        self.stats.total = len(refs)
        self.stats.skipped = len(refs) - len(pending)
        self.progress.skipped(self.stats.skipped)
        try:
            for record in self._records(pending):
                self.store.append_record(record)
                self.progress.written(1)
        except BaseException:
            if self.executions is not None:
                self.executions.close(cancel=True)
            raise
        finally:
            self._count()
        if self.executions is not None:
            self.executions.close()
        return self.stats

    def _records(self, pending: Sequence[EpisodeRef]) -> Iterator[EpisodeRecord]:
        """The records of the episodes as they end: a batch's round 0 (those not executed), and,
        between batches and after the last, those whose rounds ended."""
        executions = self.executions
        for batch in _chunks(pending, self.plan.generation.batch_size):
            self.stop.check()
            yield from self._first_round(batch)
            if executions is not None:
                yield from executions.collect(block=False, timeout=STOP_POLL_S)
                yield from executions.replans()
        while executions is not None and executions.in_flight:
            self.stop.check()
            yield from executions.collect(block=True, timeout=STOP_POLL_S)
            yield from executions.replans()

    def _first_round(self, batch: Sequence[EpisodeRef]) -> Iterator[EpisodeRecord]:
        """Answer and score a batch's round 0; yields the records of the episodes that end with
        it (the others are sent to execute)."""
        prepared = [self._prepare(ref) for ref in batch]
        answers = self.answers.answer([p.question for p in prepared])
        for p, answer in zip(prepared, answers, strict=True):
            record = answered_record(p.info, p.episode, answer, self.plan.config.scoring)
            self.progress.generated(1)
            if record.ok:
                self.stats.scored += 1
            if record.ok and self.executions is not None:
                self.stop.check()
                finished = self.executions.submit(p.episode, record, p.question.request)
                if finished is None:
                    continue  # written when its execution finishes
                record = finished
            yield record

    def ask_model(self, asks: Sequence[ReplanAsk]) -> Iterator[Answer]:
        """Answer replans a generation batch at a time (the stop flag read before each)."""
        plan = self.plan
        questions = [self._replan_question(a) for a in asks]
        for start in range(0, len(questions), plan.generation.batch_size):
            self.stop.check()
            yield from self.answers.answer(questions[start : start + plan.generation.batch_size])

    def _replan_question(self, ask: ReplanAsk) -> Question:
        plan = self.plan
        request, prompt_hash = replan_generation_request(
            ask.key,
            ask.episode,
            ask.replan,
            plan.prompts[ask.variant],
            ask.conversation,
            constrained=plan.generation.constrained,
            show_images=bool(plan.shown.views),
        )
        return Question(ask.key, prompt_hash, request)

    def _prepare(self, ref: EpisodeRef) -> _Prepared:
        plan = self.plan
        episode = self._episode
        if episode is None or episode.task_id != ref.task_id or episode.seed != ref.seed:
            episode = self._episode = get_episode(ref.task_id, ref.seed)
        images = self.snapshots.images(episode) if plan.backend.sees_images else None
        options = plan.prompts[ref.variant]
        prompt, request = prompt_request(ref, episode, images, options, plan.generation.constrained)
        info = EpisodeInfo(
            self.store.paths.run_id,
            ref.key,
            ref.variant,
            plan.config.model,
            prompt.prompt_hash,
            object_order=prompt.object_order,
            first_target_visible=first_target_visible(episode),
        )
        return _Prepared(episode, info, Question(ref.key, prompt.prompt_hash, request))

    def _count(self) -> None:
        """Copy the answers' and the executions' counts into the stats."""
        a = self.answers.stats
        self.stats.cached, self.stats.errors = a.cached, a.errors
        self.stats.generate_calls = a.generate_calls
        self.stats.error_messages = list(a.error_messages)
        if self.executions is not None:
            r = self.executions.stats
            self.stats.executed = r.executed
            self.stats.exec_crashes = r.crashes
            self.stats.exec_crash_messages = list(r.crash_messages)
