"""Closed-loop episodes (``--loop closed``; docs/design.md#closed-loop): execute, and after a failed
round, replan from the state it left.

:class:`LoopExecutions` stands where :class:`~vlm_bench.runner.executions.Executions` stands in an
open-loop run. It takes round 0's scored record (exactly the open-loop record), executes its
plan in the pool and, when the round fails, asks for a replan (:meth:`LoopExecutions.requests`)
whose answer (:meth:`LoopExecutions.answer`) executes from where the last round stopped: every
job runs all of the episode's rounds in one simulation (:mod:`~vlm_bench.runner.loop_jobs`).
An episode ends at success, after ``max_rounds`` replans, when the step budget is spent, or when
an answer holds no plan; its record is round 0's with ``rounds`` and ``loop`` added.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import partial

from vlm_bench.backends.builtin import round_request_id
from vlm_bench.parsing import parse_plan, plan_json_schema
from vlm_bench.prompting import build_replan_prompt
from vlm_bench.runner.execution_pools import ExecutionPool
from vlm_bench.runner.executions import ExecutionStats, lost_record
from vlm_bench.runner.loop_jobs import LoopJob, RoundsExecuted, StateRequest, execute_rounds
from vlm_bench.runner.loop_rounds import (
    Turns,
    chain_hash,
    history_turns,
    kept_request,
    loop_outcome,
    ran_steps,
)
from vlm_bench.runner.pending_jobs import PendingJobs
from vlm_bench.runner.plan_executor import record_plan
from vlm_bench.types.closed_loop import ExecutedStep, Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionOptions, ExecutionSummary
from vlm_bench.types.generation import (
    GenerationRequest,
    RequestMeta,
)
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.rounds import LoopEnd, RoundRecord
from vlm_bench.types.run import RunConfig

Steps = tuple[UavStep | ArmStep, ...]


@dataclass(frozen=True)
class Ask:
    """A replan to generate: the request and its cache key."""

    key: str
    """Episode key."""
    prompt_hash: str
    request: GenerationRequest


@dataclass
class _Live:
    episode: Episode
    first: EpisodeRecord
    budget: int
    turns: Turns = field(default_factory=list)
    """Each answered round: its request (None where not given), answer text, cache key."""
    plans: list[Steps] = field(default_factory=list)
    rounds: list[RoundRecord] = field(default_factory=list)
    executed: list[ExecutedStep] = field(default_factory=list)
    ask: Ask | None = None
    feedback: Feedback | None = None
    snapshot: bytes | None = None
    """The live episode frozen where the last round left it (the next round starts there)."""

    def executions(self) -> list[ExecutionSummary | None]:
        return [self.first.execution, *(r.execution for r in self.rounds)]

    def steps_used(self) -> int:
        return len(self.executed)


class LoopExecutions:
    """Runs closed-loop episodes on a pool (see module doc).

    Args:
        pool: Where the rounds execute.
        config: The run's configuration (loop, perturbations, prompt and view options).
        on_change: Called with (submitted, finished, running, queued) after every change.
        stall_s: Longest time with rounds executing and none finishing (s); default:
            :attr:`ExecutionOptions.stall_s <vlm_bench.types.execution.ExecutionOptions.stall_s>`.
        sees_images: The planner reads images; False: replans' views are not rendered.

    An execution the infrastructure loses (its worker died
    :data:`~vlm_bench.runner.pending_jobs.MAX_ATTEMPTS` times, Ray gave up, or no execution
    finished for ``stall_s``) ends its episode as an ``error`` record
    (:func:`~vlm_bench.runner.executions.lost_record`), which a resume runs again from the cached
    answers; an exception of the executor stays a recorded ``executor_crash``.
    """

    def __init__(
        self,
        pool: ExecutionPool,
        config: RunConfig,
        on_change: Callable[[int, int, int, int], None] | None = None,
        stall_s: float | None = None,
        sees_images: bool = True,
    ) -> None:
        self.pool = pool
        self.config = config
        self.views = config.views if config.images and sees_images else ()
        """The views a replan shows (none where nobody looks at them)."""
        self.executor = config.executor_config()
        """Every round's executor settings (built once)."""
        self.stall_s = ExecutionOptions().stall_s if stall_s is None else stall_s
        self.stats = ExecutionStats()
        self._notify = on_change
        self._live: dict[str, _Live] = {}
        self._running: PendingJobs[str, LoopJob, RoundsExecuted] = PendingJobs(
            pool,
            partial(pool.submit_call, execute_rounds),
            lambda job: job.key,
            self.stall_s,
            keep_done=False,  # results hold snapshots and views: held only while needed
        )
        """The job of each episode executing, by episode key."""
        self._asks: list[Ask] = []

    @property
    def in_flight(self) -> int:
        """Episodes not finished (executing, or waiting for a replan)."""
        return len(self._live)

    def submit(
        self, episode: Episode, record: EpisodeRecord, request: GenerationRequest | None = None
    ) -> EpisodeRecord | None:
        """Start an episode from round 0's record (and its request, the first turn of a
        replan's conversation); the finished record where it has no plan to execute, else
        None (it comes back from :meth:`collect` or :meth:`answer`)."""
        self.stats.submitted += 1
        steps = record_plan(record)
        budget = self.config.loop_config().budget(len(episode.gt_plan))
        live = _Live(episode, record.model_copy(update={"execution": None}), budget)
        live.turns.append(
            (kept_request(request, self.config.history), record.raw_output, record.prompt_hash)
        )
        if steps is None:
            self.stats.finished += 1
            return self._finish(live, "no_plan")
        live.plans.append(tuple(steps))
        self._live[record.key] = live
        self._send(record.key, live)
        return None

    def requests(self) -> list[Ask]:
        """The replans waiting for an answer (each handed out once)."""
        asks, self._asks = self._asks, []
        return asks

    def answer(self, ask: Ask, response: CachedResponse, cached: bool) -> EpisodeRecord | None:
        """Execute a replan's answer; the finished record where it ends the episode."""
        live = self._live[ask.key]
        assert live.feedback is not None  # set with the ask
        parse = parse_plan(response.text, live.episode.object_ids())
        steps = tuple(parse.valid_steps()) if parse.usable else ()
        left = live.budget - live.steps_used()
        row = RoundRecord(
            round=len(live.rounds) + 1,
            prompt_hash=ask.prompt_hash,
            feedback=live.feedback,
            raw_output=response.text,
            parse=parse,
            plan=plan_to_json(list(steps[:left])),
            truncated=max(0, len(steps) - left),
            latency_s=response.latency_s,
            prompt_tokens=response.prompt_tokens,
            completion_tokens=response.completion_tokens,
            finish_reason=response.finish_reason,
            cached=cached,
        )
        live.rounds.append(row)
        live.turns.append(
            (kept_request(ask.request, self.config.history), response.text, ask.prompt_hash)
        )
        if not steps:
            return self._finish(live, "no_plan")
        live.plans.append(steps[:left])
        self._send(ask.key, live)
        return None

    def fail(self, ask: Ask, error: str, latency_s: float = 0.0) -> EpisodeRecord:
        """The error record of an episode whose replan the backend failed to answer (a resume
        runs it again from round 0, its answers so far from the cache)."""
        live = self._live.pop(ask.key)
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

    def collect(self, block: bool = False, timeout: float | None = None) -> list[EpisodeRecord]:
        """Records of episodes that ended (``block``: wait for an execution to finish, or
        ``timeout`` seconds)."""
        if block:
            self._running.wait(timeout)
        out: list[EpisodeRecord] = []
        for done in self._running.finished():
            key = done.owner
            try:
                executed = done.future.result()
            # The executor's own exceptions come back as crash summaries (execute_rounds): what
            # the future raises is the infrastructure's (a dead worker or node, Ray giving up).
            except Exception as exc:  # noqa: BLE001  (an execution failure must not kill a run)
                out.append(self._lost(key, f"{type(exc).__name__}: {exc}"))
                continue
            record = self._advance(key, executed)
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
        """Free the pool (``cancel``: drop the executions in flight)."""
        self.pool.close(cancel=cancel)

    # ---- internals --------------------------------------------------------------------
    def _send(self, key: str, live: _Live) -> None:
        c = self.config
        state = None
        if len(live.plans) <= c.max_rounds:
            state = StateRequest(tuple(self.views), c.resolution, c.labels)
        ep = live.episode
        job = LoopJob(ep.task_id, ep.seed, self.executor, tuple(live.plans), state, live.snapshot)
        live.snapshot = None  # the job holds it while it runs
        if self._running.add(key, job):
            self.stats.executed += 1
        self._changed()

    def _lost(self, key: str, reason: str) -> EpisodeRecord:
        """The episode's record as one a resume runs again (its execution was lost)."""
        self.stats.lost += 1
        live = self._live.pop(key)
        self._changed()
        return lost_record(live.first, reason)

    def _advance(self, key: str, executed: RoundsExecuted) -> EpisodeRecord | None:
        live = self._live[key]
        summary = executed.executions[-1]
        if executed.crash is not None:
            self.stats.crashes += 1
            if len(self.stats.crash_messages) < 5:
                self.stats.crash_messages.append(f"{key}: {executed.crash}")
        live.snapshot = executed.snapshot
        if live.rounds:
            live.rounds[-1] = live.rounds[-1].model_copy(update={"execution": summary})
        else:
            live.first = live.first.model_copy(update={"execution": summary})
        if executed.crash is None:
            live.executed.extend(ran_steps(live.plans[-1], summary))
        if summary.exec_success:
            return self._finish(live, "success")
        if len(live.plans) > self.config.max_rounds:
            return self._finish(live, "max_rounds")
        if executed.crash is not None or executed.state is None:
            return self._finish(live, "executor_crash")
        if live.steps_used() >= live.budget:
            return self._finish(live, "budget")
        self._ask(key, live, executed)
        return None

    def _ask(self, key: str, live: _Live, executed: RoundsExecuted) -> None:
        state, ep, summary = executed.state, live.episode, executed.executions[-1]
        assert state is not None
        feedback = Feedback(
            round=len(live.plans),
            executed=tuple(live.executed),
            held=state.held,
            incomplete=summary.steps_ok,
        )
        images = state.images if self.views else None
        config = self.config.prompt_config(live.first.variant)
        prompt = build_replan_prompt(ep, state.now, images, config, feedback, state.digest)
        object_ids = ep.object_ids()
        meta = RequestMeta(
            task_id=ep.task_id,
            seed=ep.seed,
            gt_plan=ep.gt_plan,
            arm_steps=tuple(ep.arm_steps()),
            object_ids=tuple(object_ids),
            round=feedback.round,
            done_steps=tuple(s.step for s in live.executed if s.status == "done"),
            held=state.held,
        )
        schema = plan_json_schema(object_ids) if self.config.generation.constrained else None
        request = prompt.to_request(
            round_request_id(key, feedback.round), episode_id=key, meta=meta, json_schema=schema
        )
        request = request.model_copy(update={"history": history_turns(live.turns)})
        live.feedback = feedback
        key_hash = chain_hash(prompt.prompt_hash, live.turns, self.config.history)
        live.ask = Ask(key, key_hash, request)
        self._asks.append(live.ask)

    def _finish(self, live: _Live, end: LoopEnd) -> EpisodeRecord:
        self._live.pop(live.first.key, None)
        outcome = loop_outcome(
            live.executions(), end, self.config.max_rounds, live.steps_used(), live.budget
        )
        self._changed()
        return live.first.model_copy(update={"rounds": tuple(live.rounds), "loop": outcome})

    def _changed(self) -> None:
        if self._notify is not None:
            in_flight = len(self._running.items)
            running = min(self.pool.workers, in_flight)
            s = self.stats
            self._notify(s.submitted, s.finished, running, in_flight - running)
