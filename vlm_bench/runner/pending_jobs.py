"""Jobs in flight on an execution pool (docs/design.md#runs): the bookkeeping of
:class:`~vlm_bench.runner.executions.Executions` (one owner per episode, open or closed loop).

Each job is sent once per key (identical jobs share one future). A worker process that dies
breaks its whole pool: the pool is restarted and the jobs in flight are sent again, each at
most :data:`MAX_ATTEMPTS` times. No job finishing for ``stall_s`` seconds while some are in
flight (a hung worker, a lost node) abandons them all. Either way the failure is the future's
exception, which the owner turns into a lost record.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import dataclass
from typing import Generic, TypeVar

from vlm_bench.runner.execution_pools import ExecutionPool, broken_future

MAX_ATTEMPTS = 3
"""Times a job is sent again after its worker process died (a pool breaks as a whole, so the
jobs in flight beside a crashing one are sent again too)."""
WORKER_DIED = "executor worker died"

O = TypeVar("O")  # noqa: E741  (the owner of a job: a record, an episode's key)
J = TypeVar("J")
R = TypeVar("R")


@dataclass
class Pending(Generic[O, J, R]):
    """One owner's job in flight."""

    owner: O
    job: J
    future: Future[R]
    attempts: int = 1


def failed(exc: BaseException) -> Future[R]:
    """A finished future holding ``exc``."""
    future: Future[R] = Future()
    future.set_exception(exc)
    return future


class PendingJobs(Generic[O, J, R]):
    """Jobs in flight, in the order they were added (see module doc).

    Args:
        pool: Where the jobs run (restarted or abandoned here).
        send: Starts a job on the pool.
        key: A job's identity (equal keys share one execution).
        stall_s: Longest time with jobs in flight and none finishing (s).
        keep_done: Keep finished jobs' results for later identical jobs (small results); else
            a result is dropped once no job in flight shares it (results holding snapshots).
    """

    def __init__(
        self,
        pool: ExecutionPool,
        send: Callable[[J], Future[R]],
        key: Callable[[J], str],
        stall_s: float,
        keep_done: bool = True,
    ) -> None:
        self.pool = pool
        self.stall_s = stall_s
        self.items: list[Pending[O, J, R]] = []
        self._send = send
        self._key = key
        self._keep_done = keep_done
        self._futures: dict[str, Future[R]] = {}
        self._last_progress = time.monotonic()

    def add(self, owner: O, job: J) -> bool:
        """Put ``owner``'s job in flight; whether it started an execution (False: an identical
        job's is shared)."""
        if not self.items:  # the stall clock runs while jobs are in flight
            self._last_progress = time.monotonic()
        key = self._key(job)
        future = self._futures.get(key)
        started = future is None
        if future is None:
            future = self._futures[key] = self._send(job)
        self.items.append(Pending(owner, job, future))
        return started

    def wait(self, timeout: float | None = None) -> None:
        """Wait until a job finishes (or ``timeout`` seconds) unless one has or none is in
        flight."""
        if self.items and not any(p.future.done() for p in self.items):
            wait({p.future for p in self.items}, timeout, return_when=FIRST_COMPLETED)

    def finished(self) -> list[Pending[O, J, R]]:
        """The jobs that finished (taken out), after sending again those a dead worker broke
        and abandoning all where none finished for :attr:`stall_s`."""
        broken = [p for p in self.items if broken_future(p.future)]
        while broken:
            self._resend(broken)
            broken = [p for p in broken if broken_future(p.future)]
        # One read of each future's state: a worker finishing between two reads would leave
        # its job in neither list, and its episode in flight for ever.
        done: list[Pending[O, J, R]] = []
        still: list[Pending[O, J, R]] = []
        for p in self.items:
            (done if p.future.done() else still).append(p)
        now = time.monotonic()
        if done:
            self._last_progress = now
        elif still and now - self._last_progress > self.stall_s:
            self._abandon(still)
            done, still = still, []
        self.items = still
        if not self._keep_done:
            shared = {id(p.future) for p in still}
            for p in done:
                key = self._key(p.job)
                if self._futures.get(key) is p.future and id(p.future) not in shared:
                    del self._futures[key]
        return done

    def distinct(self) -> int:
        """Executions in flight (jobs sharing one count once)."""
        return len({id(p.future) for p in self.items})

    def running(self) -> int:
        """Executions running now (the rest of those in flight are queued)."""
        futures = {id(p.future): p.future for p in self.items}.values()
        return min(self.pool.workers, sum(1 for f in futures if f.running() or f.done()))

    def _abandon(self, stalled: list[Pending[O, J, R]]) -> None:
        self.pool.abandon()
        reason = f"no execution finished for {self.stall_s:g} s (a hung worker or a lost node)"
        for p in stalled:
            p.future = failed(TimeoutError(reason))
        self._futures.clear()

    def _resend(self, broken: list[Pending[O, J, R]]) -> None:
        self.pool.restart()
        renewed: dict[str, Future[R]] = {}
        for p in broken:
            if p.attempts >= MAX_ATTEMPTS:
                p.future = failed(RuntimeError(f"{WORKER_DIED} {MAX_ATTEMPTS} times"))
                continue
            key = self._key(p.job)
            if key not in renewed:
                renewed[key] = self._futures[key] = self._send(p.job)
            p.future, p.attempts = renewed[key], p.attempts + 1
