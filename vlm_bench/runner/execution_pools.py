"""Where executions run (docs/design.md#runs): the calling process, or worker processes of this
machine (Ray tasks on a cluster: :mod:`vlm_bench.runner.executions_ray`). :func:`make_pool`
picks one from the run's options.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import threading
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from multiprocessing import spawn
from multiprocessing.context import BaseContext, SpawnProcess
from typing import Any, Protocol, TypeVar

from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job
from vlm_bench.runner.worker_lifetime import die_with_parent
from vlm_bench.types.execution import ExecutionOptions

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


_MAIN_KEYS = ("init_main_from_path", "init_main_from_name")
"""What a spawned child uses to re-run the parent's ``__main__`` (``multiprocessing.spawn``)."""
_LAUNCHING = threading.Lock()
_stdlib_preparation = spawn.get_preparation_data


def _preparation_without_main(name: str) -> dict[str, Any]:
    data = _stdlib_preparation(name)
    for key in _MAIN_KEYS:
        data.pop(key, None)
    return data


def _package_popen(process_obj: Any) -> Any:
    """Start a spawned worker that does not run the parent's ``__main__``.

    A spawned child normally re-runs the parent's main script (as ``__mp_main__``) so that
    functions defined there unpickle; our workers only run vlm-bench's own functions, and
    re-running a user's script without an ``if __name__ == "__main__":`` guard would start
    the run again inside every worker. The main-module entries are left out of the data the
    child is prepared from, for this launch only (under a lock).
    """
    from multiprocessing import popen_spawn_posix

    with _LAUNCHING:
        spawn.get_preparation_data = _preparation_without_main
        try:
            return popen_spawn_posix.Popen(process_obj)
        finally:
            spawn.get_preparation_data = _stdlib_preparation


class _PackageWorker(SpawnProcess):
    _Popen = staticmethod(_package_popen)


class _PackageSpawnContext(BaseContext):
    """``spawn`` whose workers never import the caller's ``__main__``."""

    _name = "spawn"
    Process = _PackageWorker


def worker_context() -> BaseContext:
    """The start method of execution workers: ``spawn`` without re-running ``__main__``
    (plain ``spawn`` where processes are not POSIX-spawned, e.g. Windows)."""
    if sys.platform == "win32":
        return multiprocessing.get_context("spawn")
    return _PackageSpawnContext()


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
    parent may hold a GPU context or an EGL renderer that a fork must not inherit; without
    re-running the caller's ``__main__``: :func:`worker_context`). The workers exit when this
    process does (:func:`~.worker_lifetime.die_with_parent`)."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self._pool = self._start()

    def _start(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=worker_context(),
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


def make_pool(options: ExecutionOptions) -> ExecutionPool:
    """The pool ``options`` ask for: inline for 0 workers, else worker processes (default:
    one per core), or Ray tasks on a cluster."""
    workers = default_workers() if options.workers is None else options.workers
    if options.backend == "ray":
        from vlm_bench.runner.executions_ray import RayPool

        pool: ExecutionPool = RayPool(max(1, workers), options.ray_address, options.stall_s)
        return pool
    if workers <= 0:
        return InlinePool()
    return ProcessPool(workers)
