"""Executions off the generation path (docs/design.md#runs): each record's episode runs its
round machine (:mod:`vlm_bench.rounds`) on a pool of worker processes (or on a Ray cluster,
:mod:`vlm_bench.runner.executions_ray`) while the backend generates the next batches.

An :class:`Executions` takes scored records, sends each round the machine asks to execute to its
pool (identical jobs share one execution: both instruction variants' same plan) and hands back
finished records, with their execution (and, in a closed loop, their rounds), in the order
episodes end. A replan the machine asks for waits until :meth:`Executions.replans` asks the
model, through the ``ask_model`` function the caller gave (the driver never calls its caller
back). An open loop is the machine with no replans.
The simulation is deterministic and every job starts from the episode's start scene (or a
frozen episode that continues one), so an outcome does not depend on the pool, the number of
workers or the order.

``workers=0`` executes inline, in the calling process, when a round is sent (no overlap: for
debugging and for callers that need the result at once).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field

from vlm_bench.parsing import parse_plan
from vlm_bench.rounds.machine import Done, Execute, RoundMachine, Step
from vlm_bench.rounds.replan_prompt import Conversation
from vlm_bench.rounds.state import ReplanRequest, StateView
from vlm_bench.runner.answers import Answer
from vlm_bench.runner.evaluate import lost_record
from vlm_bench.runner.execution_jobs import Executed, ExecutionJob
from vlm_bench.runner.execution_pools import ExecutionPool
from vlm_bench.runner.pending_jobs import PendingJobs
from vlm_bench.runner.plan_executor import record_plan
from vlm_bench.types.closed_loop import HistoryMode, LoopConfig
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionOptions, ExecutorConfig
from vlm_bench.types.generation import GenerationRequest
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.rounds import RoundRecord
from vlm_bench.types.task import InstructionVariant


@dataclass
class ExecutionStats:
    """Counts of one :class:`Executions`."""

    submitted: int = 0
    """Records whose plans were sent (or shared an execution)."""
    executed: int = 0
    """Executions run (identical jobs run once)."""
    finished: int = 0
    """Records handed back."""
    crashes: int = 0
    """Executions that ended in an executor exception (recorded as failures)."""
    crash_messages: list[str] = field(default_factory=list)
    """``key: reason`` of the first few crashes."""
    lost: int = 0
    """Records whose execution the infrastructure lost (written as errors a resume retries)."""


@dataclass(frozen=True)
class ReplanAsk:
    """A replan an episode waits for: what its request is made of."""

    key: str
    """Episode key."""
    episode: Episode
    variant: InstructionVariant
    replan: ReplanRequest
    """The machine's feedback and the state the replan starts from."""
    conversation: Conversation
    """The rounds answered before it."""


AskModel = Callable[[Sequence[ReplanAsk]], Iterable[Answer]]
"""Answers replans, one answer per ask, in order (lazily: each is used before the next is
asked for)."""


@dataclass
class _Live:
    episode: Episode
    first: EpisodeRecord
    machine: RoundMachine
    conversation: Conversation
    plans: list[tuple[Step, ...]] = field(default_factory=list)
    rounds: list[RoundRecord] = field(default_factory=list)
    replan: ReplanRequest | None = None
    frozen: bytes | None = None
    """The live episode frozen where the last round left it (the next round starts there)."""


class Executions:
    """Drives every submitted episode's round machine on a pool (see module doc).

    Args:
        pool: Where the rounds execute.
        executor: The executor's settings of every round (gusts, perturbations).
        loop: The closed loop's settings (None: an open loop, one round an episode).
        shown: The views a replan shows (none where nobody looks at them).
        history: How a replan's conversation shows earlier rounds.
        ask_model: Answers replans (needed by a closed loop).
        on_change: Called with (submitted, finished, running, queued) after every change.
        stall_s: Longest time with executions in flight and none finishing (s); default:
            :attr:`ExecutionOptions.stall_s <vlm_bench.types.execution.ExecutionOptions.stall_s>`.

    An execution the infrastructure loses (its worker died
    :data:`~vlm_bench.runner.pending_jobs.MAX_ATTEMPTS` times, Ray gave up, or no execution
    finished for ``stall_s``) ends its episode as an ``error`` record (:func:`lost_record`),
    which a resume runs again from the cached answers; an exception of the executor stays a
    recorded ``executor_crash``.
    """

    def __init__(
        self,
        pool: ExecutionPool,
        executor: ExecutorConfig,
        loop: LoopConfig | None = None,
        *,
        shown: StateView | None = None,
        history: HistoryMode = "text",
        ask_model: AskModel | None = None,
        on_change: Callable[[int, int, int, int], None] | None = None,
        stall_s: float | None = None,
    ) -> None:
        self.pool = pool
        self.executor = executor
        self.loop = loop
        self.view = shown or StateView()
        self.history: HistoryMode = history
        self.stall_s = ExecutionOptions().stall_s if stall_s is None else stall_s
        self.stats = ExecutionStats()
        self._ask_model = ask_model
        self._notify = on_change
        self._live: dict[str, _Live] = {}
        self._running: PendingJobs[str, ExecutionJob, Executed] = PendingJobs(
            pool,
            pool.submit,
            lambda job: job.key,
            self.stall_s,
            keep_done=loop is None,  # closed-loop results hold frozen episodes and views
        )
        self._asks: list[ReplanAsk] = []

    @property
    def in_flight(self) -> int:
        """Episodes not finished (executing, or waiting for a replan)."""
        return len(self._live)

    @property
    def waiting(self) -> int:
        """Episodes waiting for a replan's answer."""
        return len(self._asks)

    def running(self) -> int:
        """Executions running now (the rest of those in flight are queued)."""
        return self._running.running()

    def submit(
        self, episode: Episode, record: EpisodeRecord, request: GenerationRequest | None = None
    ) -> EpisodeRecord | None:
        """Start an episode from round 0's scored record (and its request, the first turn of a
        replan's conversation); the finished record where it has no plan to execute, else
        None (it comes back from :meth:`collect` or :meth:`replans`)."""
        self.stats.submitted += 1
        if self.loop is not None:
            machine = RoundMachine.closed(self.loop, len(episode.gt_plan))
        else:
            machine = RoundMachine()
        conversation = Conversation(self.history)
        conversation.add(request, record.raw_output, record.prompt_hash)
        first = record.model_copy(update={"execution": None})
        live = _Live(episode, first, machine, conversation)
        self._live[record.key] = live
        action = machine.start(record_plan(record))
        if isinstance(action, Done):
            self.stats.finished += 1
            return self._finish(live, action)
        self._send(record.key, live, action)
        return None

    def replans(self) -> Iterator[EpisodeRecord]:
        """Ask the model for the replans episodes wait for and execute the answers; yields the
        records of episodes that ended (no plan, or a failed generation: an error record a
        resume runs again from round 0, its answers so far from the cache)."""
        asks, self._asks = self._asks, []
        if not asks:
            return
        if self._ask_model is None:
            raise RuntimeError("a closed loop's executions need ask_model")
        for ask, answer in zip(asks, self._ask_model(asks), strict=True):
            if answer.response is None:
                yield self._failed(ask.key, answer.error or "", answer.latency_s)
                continue
            record = self._answered(ask.key, answer)
            if record is not None:
                yield record

    def collect(self, block: bool = False, timeout: float | None = None) -> list[EpisodeRecord]:
        """Records of episodes that ended (``block``: wait for an execution to finish, or
        ``timeout`` seconds)."""
        if block:
            self._running.wait(timeout)
        out: list[EpisodeRecord] = []
        for done in self._running.finished():
            try:
                executed = done.future.result()
            # The executor's own exceptions come back as crash outcomes (execute_job): what
            # the future raises is the infrastructure's (a dead worker or node, Ray giving up).
            except Exception as exc:  # noqa: BLE001  (an execution failure must not kill a run)
                out.append(self._lost(done.owner, f"{type(exc).__name__}: {exc}"))
                continue
            record = self._advance(done.owner, executed)
            if record is not None:
                out.append(record)
        self.stats.finished += len(out)
        self._changed()
        return out

    def drain(self) -> Iterator[EpisodeRecord]:
        """Records as episodes end, while none waits for a replan's answer."""
        while self._running.items:
            yield from self.collect(block=True)

    def close(self, cancel: bool = False) -> None:
        """Free the pool (``cancel``: drop the executions in flight, e.g. on Ctrl-C)."""
        self.pool.close(cancel=cancel)

    # ---- internals --------------------------------------------------------------------
    def _answered(self, key: str, answer: Answer) -> EpisodeRecord | None:
        """Execute a replan's answer; the finished record where it ends the episode."""
        live = self._live[key]
        assert live.replan is not None and answer.response is not None  # set with the ask
        question, response = answer.question, answer.response
        parse = parse_plan(response.text, live.episode.object_ids())
        live.conversation.add(question.request, response.text, question.prompt_hash)
        action = live.machine.answered(parse.valid_steps() if parse.usable else None)
        steps = action.steps if isinstance(action, Execute) else ()
        live.rounds.append(
            RoundRecord(
                round=live.replan.round,
                prompt_hash=question.prompt_hash,
                feedback=live.replan.feedback,
                raw_output=response.text,
                parse=parse,
                plan=plan_to_json(list(steps)),
                truncated=action.truncated if isinstance(action, Execute) else 0,
                latency_s=response.latency_s,
                prompt_tokens=response.prompt_tokens,
                completion_tokens=response.completion_tokens,
                finish_reason=response.finish_reason,
                cached=answer.cached,
            )
        )
        if isinstance(action, Done):
            return self._finish(live, action)
        self._send(key, live, action)
        return None

    def _failed(self, key: str, error: str, latency_s: float) -> EpisodeRecord:
        """The error record of an episode whose replan the backend failed to answer."""
        live = self._live.pop(key)
        self._changed()
        return live.first.model_copy(
            update={
                "raw_output": "",
                "parse": None,
                "plan": None,
                "scores": None,
                "execution": None,
                "error_tags": ("backend_error",),
                "backend_error": f"round {len(live.rounds) + 1}: {error}",
                "latency_s": latency_s,
                "status": "error",
            }
        )

    def _send(self, key: str, live: _Live, action: Execute) -> None:
        live.plans.append(action.steps)
        more = len(live.plans) <= live.machine.max_replans  # a replan may follow this round
        ep = live.episode
        job = ExecutionJob(
            ep.task_id,
            ep.seed,
            self.executor,
            tuple(live.plans),
            self.view if more else None,
            live.frozen,
        )
        live.frozen = None  # the job holds it while it runs
        if self._running.add(key, job):
            self.stats.executed += 1
        self._changed()

    def _lost(self, key: str, reason: str) -> EpisodeRecord:
        """The episode's record as one a resume runs again (its execution was lost)."""
        self.stats.lost += 1
        live = self._live.pop(key)
        self._changed()
        return lost_record(live.first, reason)

    def _advance(self, key: str, executed: Executed) -> EpisodeRecord | None:
        live = self._live[key]
        outcome = executed.outcomes[-1]
        if executed.crash is not None:
            self.stats.crashes += 1
            if len(self.stats.crash_messages) < 5:
                self.stats.crash_messages.append(f"{key}: {executed.crash}")
        live.frozen = executed.frozen
        if live.rounds:
            live.rounds[-1] = live.rounds[-1].model_copy(update={"execution": outcome.execution})
        else:
            live.first = live.first.model_copy(update={"execution": outcome.execution})
        action = live.machine.executed_round(outcome)
        if isinstance(action, Done):
            return self._finish(live, action)
        if executed.state is None:  # a replan without the state it plans from cannot be asked
            raise RuntimeError(f"{key}: round {len(live.plans) - 1} left no state to replan from")
        live.replan = ReplanRequest(action.feedback, executed.state)
        self._asks.append(
            ReplanAsk(key, live.episode, live.first.variant, live.replan, live.conversation)
        )
        return None

    def _finish(self, live: _Live, done: Done) -> EpisodeRecord:
        self._live.pop(live.first.key, None)
        self._changed()
        if self.loop is None:
            return live.first
        return live.first.model_copy(update={"rounds": tuple(live.rounds), "loop": done.outcome})

    def _changed(self) -> None:
        if self._notify is not None:
            running = self.running()
            in_flight = self._running.distinct()
            s = self.stats
            self._notify(s.submitted, s.finished, running, in_flight - running)
