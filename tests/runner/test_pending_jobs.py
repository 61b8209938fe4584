"""The bookkeeping of jobs in flight: a job that finishes while :meth:`PendingJobs.finished`
looks at the futures is returned (now or at the next call), never dropped."""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any

from vlm_bench.runner.pending_jobs import PendingJobs


class _FinishesWhileRead(Future[str]):
    """A future a worker finishes right after the owner's second read of its state (the
    first is the check for a dead worker; the executor's manager thread sets results while
    the owner reads them)."""

    def __init__(self) -> None:
        super().__init__()
        self.reads = 0

    def done(self) -> bool:
        was = super().done()
        self.reads += 1
        if self.reads == 2:
            self.set_result("executed")
        return was


class _Pool:
    workers = 1

    def restart(self) -> None:
        return None

    def abandon(self) -> None:
        return None


def test_a_job_finishing_during_finished_is_not_lost() -> None:
    future = _FinishesWhileRead()
    jobs: PendingJobs[str, str, str] = PendingJobs(
        _Pool(),  # type: ignore[arg-type]
        lambda _job: future,
        lambda job: job,
        stall_s=60.0,
    )
    jobs.add("episode", "job")
    first = jobs.finished()
    second = jobs.finished()
    returned: list[Any] = [p.owner for p in (*first, *second)]
    assert returned == ["episode"]
    assert jobs.items == []
