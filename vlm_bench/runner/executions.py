"""Plan executions off the generation path (docs/design.md#runs): records' plans execute in a
pool of worker processes (or on a Ray cluster, :mod:`vlm_bench.runner.executions_ray`) while the
backend generates the next batches.

An :class:`Executions` takes scored records, sends each usable plan to its pool once per episode
(identical plans on the same episode, e.g. both instruction variants, share one execution) and
hands back finished records, with their execution attached, in the order executions finish. The
simulation is deterministic and every execution starts from the episode's freshly compiled scene,
so an outcome does not depend on the pool, the number of workers or the order.

``workers=0`` executes inline, in the calling process, when a record is submitted (no overlap:
for debugging and for callers that need the result at once).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job
from vlm_bench.runner.execution_pools import (
    ExecutionPool,
    InlinePool,
    ProcessPool,
    broken_future,
    default_workers,
)
from vlm_bench.runner.pending_jobs import MAX_ATTEMPTS, WORKER_DIED, Pending, PendingJobs
from vlm_bench.runner.plan_executor import record_plan
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionOptions, ExecutorConfig
from vlm_bench.types.records import EpisodeRecord

__all__ = [
    "EXECUTION_LOST",
    "MAX_ATTEMPTS",
    "WORKER_DIED",
    "Executed",
    "ExecutionJob",
    "ExecutionPool",
    "ExecutionStats",
    "Executions",
    "InlinePool",
    "ProcessPool",
    "broken_future",
    "default_workers",
    "execute_job",
    "lost_record",
    "make_pool",
]

EXECUTION_LOST = "execution lost to the infrastructure"
"""Start of the message of a record whose execution the infrastructure lost (retried on resume)."""


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


@dataclass
class ExecutionStats:
    """Counts of one :class:`Executions`."""

    submitted: int = 0
    """Records whose plans were sent (or shared an execution)."""
    executed: int = 0
    """Executions run (identical plans on one episode run once)."""
    finished: int = 0
    """Records handed back with their execution."""
    crashes: int = 0
    """Executions that ended in an executor exception (recorded as failures)."""
    crash_messages: list[str] = field(default_factory=list)
    """``key: reason`` of the first few crashes."""
    lost: int = 0
    """Records whose execution the infrastructure lost (written as errors a resume retries)."""


class Executions:
    """Executes records' plans on a pool; hands records back as their executions finish.

    An execution lost to the infrastructure (its worker died :data:`MAX_ATTEMPTS` times, Ray
    gave up on it, or no execution finished for ``stall_s`` seconds: a hung worker, a dead node;
    :mod:`~vlm_bench.runner.pending_jobs`)
    hands its record back as an ``error`` record (:data:`EXECUTION_LOST`), which a resume runs
    again; an exception of the executor on the plan stays a recorded ``executor_crash``.

    Args:
        pool: Where executions run.
        config: Executor settings of every execution (gusts, perturbations; default: none).
        on_change: Called with (submitted, finished, running, queued) after every change
            (progress displays).
        stall_s: Longest time with executions in flight and none finishing (s); default:
            :attr:`ExecutionOptions.stall_s <vlm_bench.types.execution.ExecutionOptions.stall_s>`.
    """

    def __init__(
        self,
        pool: ExecutionPool,
        config: ExecutorConfig | None = None,
        on_change: Callable[[int, int, int, int], None] | None = None,
        stall_s: float | None = None,
    ) -> None:
        self.pool = pool
        self.config = config or ExecutorConfig()
        self.stats = ExecutionStats()
        self.stall_s = ExecutionOptions().stall_s if stall_s is None else stall_s
        self._notify = on_change
        self._pending: PendingJobs[EpisodeRecord, ExecutionJob, Executed] = PendingJobs(
            pool, pool.submit, lambda job: job.key, self.stall_s
        )
        """Records waiting for their execution: a second record with the same plan waits on the
        first's."""

    @property
    def in_flight(self) -> int:
        """Records waiting for their execution."""
        return len(self._pending.items)

    def running(self) -> int:
        """Executions running now (the rest of those in flight are queued)."""
        return self._pending.running()

    def submit(self, episode: Episode, record: EpisodeRecord) -> EpisodeRecord | None:
        """Send ``record``'s plan to the pool; the record itself, with no execution, where it
        has no usable plan (it is finished), else None (it comes back from :meth:`collect`)."""
        steps = record_plan(record)
        if steps is None:
            return record.model_copy(update={"execution": None})
        job = ExecutionJob(episode.task_id, episode.seed, self.config, tuple(steps))
        if self._pending.add(record, job):
            self.stats.executed += 1
        self.stats.submitted += 1
        self._changed()
        return None

    def collect(self, block: bool = False, timeout: float | None = None) -> list[EpisodeRecord]:
        """Records whose executions finished (with ``block``, waits for at least one while any
        is in flight, or ``timeout`` seconds)."""
        if block:
            self._pending.wait(timeout)
        out = [self._finish(p) for p in self._pending.finished()]
        if out:
            self.stats.finished += len(out)
        self._changed()
        return out

    def drain(self) -> Iterator[EpisodeRecord]:
        """Every remaining record, as executions finish."""
        while self._pending.items:
            yield from self.collect(block=True)

    def close(self, cancel: bool = False) -> None:
        """Free the pool (``cancel``: drop the executions in flight, e.g. on Ctrl-C)."""
        self.pool.close(cancel=cancel)

    def _finish(self, p: Pending[EpisodeRecord, ExecutionJob, Executed]) -> EpisodeRecord:
        try:
            summary, crash = p.future.result()
        # The executor's own exceptions come back as crash summaries (PlanExecutor.execute): what
        # the future raises is the infrastructure's (a dead worker or node, Ray giving up).
        except Exception as exc:  # noqa: BLE001  (an execution failure must not kill the run)
            self.stats.lost += 1
            return lost_record(p.owner, f"{type(exc).__name__}: {exc}")
        if crash is not None:
            self._crashed(p.owner.key, crash)
        return p.owner.model_copy(update={"execution": summary})

    def _changed(self) -> None:
        if self._notify is not None:
            running = self.running()
            in_flight = self._pending.distinct()
            s = self.stats
            self._notify(s.submitted, s.finished, running, in_flight - running)

    def _crashed(self, key: str, message: str) -> None:
        self.stats.crashes += 1
        if len(self.stats.crash_messages) < 5:
            self.stats.crash_messages.append(f"{key}: {message}")


def lost_record(record: EpisodeRecord, reason: str) -> EpisodeRecord:
    """``record`` as an ``error`` record whose execution the infrastructure lost: a resume scores
    its cached answer again and executes it."""
    return record.model_copy(
        update={
            "status": "error",
            "execution": None,
            "backend_error": f"{EXECUTION_LOST} ({reason}); a resume runs it again",
            "error_tags": ("execution_lost",),
        }
    )
