"""Plan replays off the generation path (docs/design.md#runs): records' plans execute in a pool of
worker processes (or on a Ray cluster, :mod:`vlm_bench.runner.replays_ray`) while the backend
generates the next batches.

A :class:`Replays` takes scored records, sends each usable plan to its pool once per episode
(identical plans on the same episode, e.g. both instruction variants, share one replay) and
hands back finished records, with their execution attached, in the order replays finish. The
simulation is deterministic and every replay starts from the episode's freshly compiled scene,
so an outcome does not depend on the pool, the number of workers or the order.

``workers=0`` replays inline, in the calling process, when a record is submitted (no overlap:
for debugging and for callers that need the result at once).
"""

from __future__ import annotations

import json
import multiprocessing
import os
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

from vlm_bench.runner.plan_executor import PlanExecutor, record_plan
from vlm_bench.runner.worker_lifetime import die_with_parent
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionSummary, ExecutorConfig, ReplayOptions
from vlm_bench.types.plan import ArmStep, UavStep, plan_to_json
from vlm_bench.types.records import EpisodeRecord

MAX_ATTEMPTS = 3
"""Times a replay is sent again after its worker process died (a pool breaks as a whole, so
the replays in flight beside a crashing one are sent again too)."""
WORKER_DIED = "executor worker died"
REPLAY_LOST = "replay lost to the infrastructure"
"""Start of the message of a record whose replay the infrastructure lost (retried on resume)."""


@dataclass(frozen=True)
class ReplayJob:
    """One plan to execute on one episode (picklable: crosses to worker processes)."""

    task_id: str
    seed: int
    config: ExecutorConfig
    """Gusts and perturbations: the run's, the same for every job."""
    steps: tuple[UavStep | ArmStep, ...]

    @property
    def key(self) -> str:
        """Identity of the replay: episode, executor settings and plan."""
        plan = json.dumps(plan_to_json(list(self.steps)), sort_keys=True)
        return f"{self.task_id}/{self.seed}/{self.config.model_dump_json()}:{plan}"


J = TypeVar("J")
R = TypeVar("R")

Replayed = tuple[ExecutionSummary, str | None]
"""A replay's summary and, where the executor raised, the message (the summary says so too)."""


class ReplayPool(Protocol):
    """Where replays run."""

    workers: int
    """Replays that run at once."""

    def submit(self, job: ReplayJob) -> Future[Replayed]:
        """Start ``job``; its future holds the outcome."""
        ...

    def submit_call(self, fn: Callable[[J], R], job: J) -> Future[R]:
        """Start ``fn(job)`` (a picklable module-level function); its future holds the
        outcome (closed-loop jobs)."""
        ...

    def restart(self) -> None:
        """Replace workers that died (a no-op where none can)."""
        ...

    def abandon(self) -> None:
        """Drop every replay in flight (hung, or on a node that is gone): stop what runs them;
        later submissions start afresh."""
        ...

    def close(self, cancel: bool = False) -> None:
        """Wait for the replays in flight (or, with ``cancel``, drop them) and free the
        workers."""
        ...


_EXECUTORS: dict[ExecutorConfig, PlanExecutor] = {}
"""Per process (each worker's own): one executor per executor config, which keeps the
compiled scene of the episode it last replayed."""


def replay(job: ReplayJob) -> Replayed:
    """Execute ``job`` in this process (what every pool runs)."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.sim.mujoco_log import route_mujoco_log

    route_mujoco_log()  # a worker writes no MUJOCO_LOG.TXT either
    executor = _EXECUTORS.get(job.config)
    if executor is None:
        executor = _EXECUTORS[job.config] = PlanExecutor(job.config)
    episode = get_episode(job.task_id, job.seed)
    return executor.run(episode, list(job.steps))


def _init_worker(parent: int) -> None:
    die_with_parent(parent)
    os.environ.setdefault("MUJOCO_GL", "egl")


class InlinePool:
    """Replays in the calling process, at submit (``--exec-workers 0``)."""

    workers = 1

    def submit(self, job: ReplayJob) -> Future[Replayed]:
        return self.submit_call(replay, job)

    def submit_call(self, fn: Callable[[J], R], job: J) -> Future[R]:
        future: Future[R] = Future()
        try:
            future.set_result(fn(job))
        except BaseException as exc:  # noqa: BLE001  (delivered through the future)
            future.set_exception(exc)
        return future

    def restart(self) -> None:
        return None

    def abandon(self) -> None:
        return None

    def close(self, cancel: bool = False) -> None:
        return None


class ProcessPool:
    """Replays in ``workers`` worker processes of this machine (started with ``spawn``: the
    parent may hold a GPU context or an EGL renderer that a fork must not inherit). The
    workers exit when this process does (:func:`~.worker_lifetime.die_with_parent`)."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self._pool = self._start()

    def _start(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=_init_worker,
            initargs=(os.getpid(),),
        )

    def submit(self, job: ReplayJob) -> Future[Replayed]:
        return self._pool.submit(replay, job)

    def submit_call(self, fn: Callable[[J], R], job: J) -> Future[R]:
        return self._pool.submit(fn, job)

    def restart(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool = self._start()

    def abandon(self) -> None:
        self.close(cancel=True)
        self._pool = self._start()

    def close(self, cancel: bool = False) -> None:
        if cancel:
            for proc in list(getattr(self._pool, "_processes", {}).values()):
                proc.terminate()  # a replay in flight takes seconds: do not wait for it
        self._pool.shutdown(wait=not cancel, cancel_futures=cancel)


def make_pool(options: ReplayOptions) -> ReplayPool:
    """The pool ``options`` ask for: inline for 0 workers, else worker processes (default:
    one per core), or Ray tasks on a cluster."""
    workers = default_workers() if options.workers is None else options.workers
    if options.backend == "ray":
        from vlm_bench.runner.replays_ray import RayPool

        pool: ReplayPool = RayPool(max(1, workers), options.ray_address)
        return pool
    if workers <= 0:
        return InlinePool()
    return ProcessPool(workers)


def default_workers() -> int:
    """The machine's cores (what ``--exec-workers`` defaults to)."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


@dataclass
class _Pending:
    record: EpisodeRecord
    job: ReplayJob
    future: Future[Replayed]
    attempts: int = 1


@dataclass
class ReplayStats:
    """Counts of one :class:`Replays`."""

    submitted: int = 0
    """Records whose plans were sent (or shared a replay)."""
    executed: int = 0
    """Replays run (identical plans on one episode run once)."""
    finished: int = 0
    """Records handed back with their execution."""
    crashes: int = 0
    """Replays that ended in an executor exception (recorded as failures)."""
    crash_messages: list[str] = field(default_factory=list)
    """``key: reason`` of the first few crashes."""
    lost: int = 0
    """Records whose replay the infrastructure lost (written as errors a resume retries)."""


class Replays:
    """Executes records' plans on a pool; hands records back as their replays finish.

    A replay lost to the infrastructure (its worker died :data:`MAX_ATTEMPTS` times, Ray
    gave up on it, or no replay finished for ``stall_s`` seconds: a hung worker, a dead node)
    hands its record back as an ``error`` record (:data:`REPLAY_LOST`), which a resume runs
    again; an exception of the executor on the plan stays a recorded ``executor_crash``.

    Args:
        pool: Where replays run.
        config: Executor settings of every replay (gusts, perturbations; default: none).
        on_change: Called with (submitted, finished, running, queued) after every change
            (progress displays).
        stall_s: Longest time with replays in flight and none finishing (s); default:
            :attr:`ReplayOptions.stall_s <vlm_bench.types.execution.ReplayOptions.stall_s>`.
    """

    def __init__(
        self,
        pool: ReplayPool,
        config: ExecutorConfig | None = None,
        on_change: Callable[[int, int, int, int], None] | None = None,
        stall_s: float | None = None,
    ) -> None:
        self.pool = pool
        self.config = config or ExecutorConfig()
        self.stats = ReplayStats()
        self.stall_s = ReplayOptions().stall_s if stall_s is None else stall_s
        self._notify = on_change
        self._last_progress = time.monotonic()
        self._pending: list[_Pending] = []
        self._futures: dict[str, Future[Replayed]] = {}
        """Replays by job key: a second record with the same plan waits on the first's."""

    @property
    def in_flight(self) -> int:
        """Records waiting for their replay."""
        return len(self._pending)

    def running(self) -> int:
        """Replays running now (the rest of those in flight are queued)."""
        futures = {id(p.future): p.future for p in self._pending}.values()
        return min(self.pool.workers, sum(1 for f in futures if f.running() or f.done()))

    def submit(self, episode: Episode, record: EpisodeRecord) -> EpisodeRecord | None:
        """Send ``record``'s plan to the pool; the record itself, with no execution, where it
        has no usable plan (it is finished), else None (it comes back from :meth:`collect`)."""
        steps = record_plan(record)
        if steps is None:
            return record.model_copy(update={"execution": None})
        job = ReplayJob(episode.task_id, episode.seed, self.config, tuple(steps))
        if not self._pending:  # the stall clock runs while replays are in flight
            self._last_progress = time.monotonic()
        future = self._futures.get(job.key)
        if future is None:
            future = self._futures[job.key] = self.pool.submit(job)
            self.stats.executed += 1
        self.stats.submitted += 1
        self._pending.append(_Pending(record, job, future))
        self._changed()
        return None

    def collect(self, block: bool = False, timeout: float | None = None) -> list[EpisodeRecord]:
        """Records whose replays finished (with ``block``, waits for at least one while any
        is in flight, or ``timeout`` seconds)."""
        if block and self._pending and not any(p.future.done() for p in self._pending):
            wait({p.future for p in self._pending}, timeout, return_when=FIRST_COMPLETED)
        broken = [p for p in self._pending if broken_future(p.future)]
        while broken:
            self._resend(broken)
            broken = [p for p in broken if broken_future(p.future)]
        done: list[_Pending] = []
        still: list[_Pending] = []
        for p in self._pending:
            (done if p.future.done() else still).append(p)
        now = time.monotonic()
        if done:
            self._last_progress = now
        elif still and now - self._last_progress > self.stall_s:
            self._abandon(still)
            done, still = still, []
        self._pending = still
        out = [self._finish(p) for p in done]
        if out:
            self.stats.finished += len(out)
        self._changed()
        return out

    def drain(self) -> Iterator[EpisodeRecord]:
        """Every remaining record, as replays finish."""
        while self._pending:
            yield from self.collect(block=True)

    def close(self, cancel: bool = False) -> None:
        """Free the pool (``cancel``: drop the replays in flight, e.g. on Ctrl-C)."""
        self.pool.close(cancel=cancel)

    def _finish(self, p: _Pending) -> EpisodeRecord:
        try:
            summary, crash = p.future.result()
        # The executor's own exceptions come back as crash summaries (PlanExecutor.run): what
        # the future raises is the infrastructure's (a dead worker or node, Ray giving up).
        except Exception as exc:  # noqa: BLE001  (a replay failure must not kill the run)
            self.stats.lost += 1
            return lost_record(p.record, f"{type(exc).__name__}: {exc}")
        if crash is not None:
            self._crashed(p.record.key, crash)
        return p.record.model_copy(update={"execution": summary})

    def _abandon(self, stalled: list[_Pending]) -> None:
        """No replay finished for :attr:`stall_s`: give up those in flight (as lost)."""
        self.pool.abandon()
        reason = f"no replay finished for {self.stall_s:g} s (a hung worker or a lost node)"
        for p in stalled:
            p.future = Future()
            p.future.set_exception(TimeoutError(reason))
        self._futures.clear()

    def _resend(self, broken: list[_Pending]) -> None:
        """A worker process died, which breaks its whole pool: start new workers and send the
        replays that were in flight again (one that has broken :data:`MAX_ATTEMPTS` pools
        is recorded as a crash)."""
        self.pool.restart()
        renewed: dict[str, Future[Replayed]] = {}
        for p in broken:
            if p.attempts >= MAX_ATTEMPTS:
                p.future = Future()
                p.future.set_exception(RuntimeError(f"{WORKER_DIED} {MAX_ATTEMPTS} times"))
                continue
            key = p.job.key
            if key not in renewed:
                renewed[key] = self._futures[key] = self.pool.submit(p.job)
            p.future, p.attempts = renewed[key], p.attempts + 1

    def _changed(self) -> None:
        if self._notify is not None:
            running = self.running()
            in_flight = len({id(p.future) for p in self._pending})
            s = self.stats
            self._notify(s.submitted, s.finished, running, in_flight - running)

    def _crashed(self, key: str, message: str) -> None:
        self.stats.crashes += 1
        if len(self.stats.crash_messages) < 5:
            self.stats.crash_messages.append(f"{key}: {message}")


def lost_record(record: EpisodeRecord, reason: str) -> EpisodeRecord:
    """``record`` as an ``error`` record whose replay the infrastructure lost: a resume scores
    its cached answer again and replays it."""
    return record.model_copy(
        update={
            "status": "error",
            "execution": None,
            "backend_error": f"{REPLAY_LOST} ({reason}); a resume runs it again",
            "error_tags": ("replay_lost",),
        }
    )


def broken_future(future: Future[Any]) -> bool:
    """Whether ``future`` failed because its worker process died (or was dropped with it)."""
    if not future.done():
        return False
    if future.cancelled():
        return True
    return isinstance(future.exception(), BrokenProcessPool)
