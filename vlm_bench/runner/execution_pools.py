"""Where executions run (docs/design.md#runs): the calling process, or worker processes of this
machine (Ray tasks on a cluster: :mod:`vlm_bench.runner.executions_ray`). :func:`make_pool` in
:mod:`vlm_bench.runner.executions` picks one from the run's options.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Protocol, TypeVar

from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job
from vlm_bench.runner.worker_lifetime import die_with_parent

J = TypeVar("J")
R = TypeVar("R")


class ExecutionPool(Protocol):
    """Where executions run."""

    workers: int
    """Executions that run at once."""

    def submit(self, job: ExecutionJob) -> Future[Executed]:
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
        """Drop every execution in flight (hung, or on a node that is gone): stop what runs them;
        later submissions start afresh."""
        ...

    def close(self, cancel: bool = False) -> None:
        """Wait for the executions in flight (or, with ``cancel``, drop them) and free the
        workers."""
        ...


def _init_worker(parent: int) -> None:
    die_with_parent(parent)
    os.environ.setdefault("MUJOCO_GL", "egl")


class InlinePool:
    """Executes in the calling process, at submit (``--exec-workers 0``)."""

    workers = 1

    def submit(self, job: ExecutionJob) -> Future[Executed]:
        return self.submit_call(execute_job, job)

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
    """Executes in ``workers`` worker processes of this machine (started with ``spawn``: the
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

    def submit(self, job: ExecutionJob) -> Future[Executed]:
        return self._pool.submit(execute_job, job)

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
                proc.terminate()  # an execution in flight takes seconds: do not wait for it
        self._pool.shutdown(wait=not cancel, cancel_futures=cancel)


def default_workers() -> int:
    """The machine's cores (what ``--exec-workers`` defaults to)."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


def broken_future(future: Future[Any]) -> bool:
    """Whether ``future`` failed because its worker process died (or was dropped with it)."""
    if not future.done():
        return False
    if future.cancelled():
        return True
    return isinstance(future.exception(), BrokenProcessPool)
