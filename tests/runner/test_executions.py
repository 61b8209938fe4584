"""Plan executions off the generation path: the same outcome whatever the pool and the number of
workers, one execution per distinct plan of an episode, dead workers replaced, progress lines."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import threading
import time
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import TYPE_CHECKING

import pytest
from rich.console import Console

import vlm_bench
from vlm_bench.episodes import get_episode
from vlm_bench.rounds import StateView
from vlm_bench.runner.evaluate import EXECUTION_LOST, EpisodeInfo, scored_record
from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job
from vlm_bench.runner.execution_pools import InlinePool, ProcessPool
from vlm_bench.runner.executions import Executions
from vlm_bench.runner.pending_jobs import MAX_ATTEMPTS, WORKER_DIED
from vlm_bench.runner.progress import RunProgress
from vlm_bench.storage import latest_records, read_records
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import (
    ExecutionOptions,
    ExecutionSummary,
    ExecutorConfig,
    FailureCode,
)
from vlm_bench.types.plan import Direction, UavStep, plan_to_json
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.run import RunConfig
from vlm_bench.types.scores import ScoringConfig

ROOT = Path(__file__).resolve().parents[2]
FAST = ("container_geometry_bowl", "slim_object_in_bowl", "clear_desk_push_box")
"""Tasks whose GT executions take ~2 s."""

if TYPE_CHECKING:
    from tests.conftest import Cli


OPEN = RunConfig(model="oracle").executor_config()
"""An open-loop run's executor settings (no gusts, no perturbations)."""


def _summary(executed: Executed) -> ExecutionSummary:
    """The execution of a one-round job."""
    return executed.outcomes[-1].execution


def _outcome(summary: ExecutionSummary | None) -> dict[str, object] | None:
    """What must not depend on where an execution ran: all but its wall time."""
    return None if summary is None else summary.model_dump(exclude={"wall_time_s"})


def _fields(record: EpisodeRecord, *leave_out: str) -> dict[str, object]:
    """The record's fields but its timing and ``leave_out``."""
    return {k: v for k, v in record.without_timing().items() if k not in leave_out}


def _jobs() -> list[ExecutionJob]:
    jobs = []
    for task in FAST[:2]:
        ep = get_episode(task, 0)
        jobs.append(ExecutionJob(task, 0, ExecutorConfig(), (tuple(ep.gt_plan),)))
        down = (UavStep(direction=Direction.DOWN, distance=0.2),)
        jobs.append(ExecutionJob(task, 0, ExecutorConfig(), (down,)))
    return jobs


def test_jobs_carry_the_runs_executor_config_across_processes() -> None:
    import pickle

    from vlm_bench.types.closed_loop import PerturbConfig

    config = RunConfig(model="m", tasks=(FAST[0],), uav_noise=2.0, perturb=PerturbConfig(bump=0.5))
    executor = config.executor_config()
    steps = (UavStep(direction=Direction.DOWN, distance=0.2),)
    job = ExecutionJob(FAST[0], 0, executor, (steps,))
    loop_job = ExecutionJob(FAST[0], 0, executor, (steps, steps), StateView(("side",), 32))
    for sent in (job, loop_job):
        back = pickle.loads(pickle.dumps(sent))
        assert back == sent and back.key == sent.key and back.config == executor
    calm = ExecutionJob(FAST[0], 0, ExecutorConfig(), (steps,))
    assert calm.key != job.key  # other settings: another execution


def test_outcomes_do_not_depend_on_the_pool_or_its_workers() -> None:
    jobs = _jobs()
    inline = [_summary(execute_job(j)) for j in jobs]
    assert inline[0].exec_success and not inline[1].exec_success
    for workers in (2,):  # one worker is covered by the run below
        pool = ProcessPool(workers)
        try:
            # reversed: each worker meets the episodes in another order than inline
            futures = [pool.submit(j) for j in reversed(jobs)]
            pooled = [_summary(f.result(timeout=300)) for f in reversed(futures)]
        finally:
            pool.close()
        assert [_outcome(s) for s in pooled] == [_outcome(s) for s in inline]


def test_ray_pool_gives_the_same_outcomes() -> None:
    pytest.importorskip("ray", reason="the ray extra is not installed")
    from vlm_bench.runner.executions_ray import RayPool

    jobs = _jobs()[:2]
    pool = RayPool(2)
    try:
        got = [_summary(f.result(timeout=300)) for f in [pool.submit(j) for j in jobs]]
        for _ in range(100):  # the refs are dropped by the futures' done-callbacks
            if pool.held == 0:
                break
            time.sleep(0.05)
        assert pool.held == 0  # finished executions do not pin their results
    finally:
        pool.close()
    assert [_outcome(s) for s in got] == [_outcome(_summary(execute_job(j))) for j in jobs]


def test_a_run_writes_the_same_records_inline_or_in_a_worker(tmp_path: Path) -> None:
    runs = {}
    for workers in (0, 1):
        result = vlm_bench.run(
            model="oracle",
            tasks=FAST,
            seeds=(0,),
            resolution=48,
            out=tmp_path / f"w{workers}",
            execution=ExecutionOptions(workers=workers),
            snapshot_cache=tmp_path / "snapshots",
        )
        assert result.stats.executed == len(FAST)  # both instructions share one execution
        by_key = {r.key: r for r in result.records}
        runs[workers] = {
            k: (
                _fields(r, "execution", "run_id"),
                _outcome(r.execution),
            )
            for k, r in sorted(by_key.items())
        }
    assert runs[0] == runs[1]
    assert all(v[1] is not None and v[1]["exec_success"] for v in runs[0].values())


class _FlakyPool:
    """A pool whose first ``breaks`` submissions fail as if their worker process died."""

    workers = 2

    def __init__(self, breaks: int) -> None:
        self.breaks = breaks
        self.submitted = 0
        self.restarts = 0

    def submit(self, job: ExecutionJob) -> Future[Executed]:
        self.submitted += 1
        future: Future[Executed] = Future()
        if self.breaks > 0:
            self.breaks -= 1
            future.set_exception(BrokenProcessPool("a worker died"))
        else:
            future.set_result(execute_job(job))
        return future

    def restart(self) -> None:
        self.restarts += 1

    def abandon(self) -> None:
        return None

    def close(self, cancel: bool = False) -> None:
        return None


class _HungPool(_FlakyPool):
    """A pool whose executions never finish (a hung worker, or a node that is gone)."""

    def __init__(self) -> None:
        super().__init__(breaks=0)
        self.abandoned = 0

    def submit(self, job: ExecutionJob) -> Future[Executed]:
        self.submitted += 1
        return Future()

    def abandon(self) -> None:
        self.abandoned += 1


def _record(task: str) -> tuple[Episode, EpisodeRecord]:
    """The episode and an oracle's scored record of it."""
    ep = get_episode(task, 0)
    text = json.dumps(plan_to_json(ep.gt_plan))
    info = EpisodeInfo("run", f"{task}/0/explicit", "explicit", "oracle", "h")
    response = CachedResponse(key=info.key, prompt_hash="h", text=text)
    return ep, scored_record(info, ep, response, ScoringConfig())


def test_a_dead_worker_is_replaced_and_the_execution_sent_again() -> None:
    ep, record = _record(FAST[0])
    pool = _FlakyPool(breaks=1)
    executions = Executions(pool, OPEN)
    assert executions.submit(ep, record) is None
    assert executions.submit(ep, record.model_copy(update={"key": "same plan"})) is None
    out = list(executions.drain())
    assert pool.restarts == 1 and pool.submitted == 2  # the shared execution was sent again once
    assert [r.execution.exec_success for r in out if r.execution] == [True, True]
    assert executions.stats.crashes == 0


def test_an_execution_that_keeps_killing_its_worker_is_lost_and_retried_on_resume() -> None:
    ep, record = _record(FAST[0])
    executions = Executions(_FlakyPool(breaks=MAX_ATTEMPTS), OPEN)
    executions.submit(ep, record)
    (out,) = list(executions.drain())
    assert out.status == "error" and out.execution is None  # not a result: a resume retries
    assert out.backend_error is not None and out.backend_error.startswith(EXECUTION_LOST)
    assert WORKER_DIED in out.backend_error and out.error_tags == ("execution_lost",)
    assert executions.stats.lost == 1 and executions.stats.crashes == 0


def test_an_executor_exception_on_a_valid_plan_stays_a_recorded_crash(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from vlm_bench.executor.live_episode import LiveEpisode

    def broken(*args: object, **kwargs: object) -> None:
        raise ZeroDivisionError("executor bug")

    monkeypatch.setattr(LiveEpisode, "execute", broken)
    ep, record = _record(FAST[0])
    executions = Executions(InlinePool(), OPEN)
    executions.submit(ep, record)
    (out,) = list(executions.drain())
    assert out.status == "ok" and out.execution is not None
    assert out.execution.failure_code is FailureCode.EXECUTOR_CRASH
    assert executions.stats.crashes == 1 and executions.stats.lost == 0


def test_executions_that_never_finish_are_given_up_within_the_stall_bound() -> None:
    ep, record = _record(FAST[0])
    pool = _HungPool()
    executions = Executions(pool, OPEN, stall_s=0.3)
    executions.submit(ep, record)
    start = time.monotonic()
    out: list[EpisodeRecord] = []
    while not out and time.monotonic() - start < 5:
        out = executions.collect(block=True, timeout=0.05)
    assert time.monotonic() - start < 2
    (lost,) = out
    assert lost.status == "error" and "no execution finished for 0.3 s" in (
        lost.backend_error or ""
    )
    assert pool.abandoned == 1 and executions.in_flight == 0


def test_a_run_whose_executions_were_lost_resumes_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from vlm_bench.runner import benchmark_run

    config = RunConfig(
        model="oracle", tasks=FAST[:2], seeds=(0,), instructions=("explicit",), resolution=32
    )
    inline = ExecutionOptions(workers=0)
    monkeypatch.setattr(benchmark_run, "make_pool", lambda options: _FlakyPool(breaks=99))
    lost = vlm_bench.run(config, out=tmp_path / "lost" / "run", execution=inline)
    assert [r.status for r in lost.records] == ["error", "error"]
    monkeypatch.undo()
    resumed = vlm_bench.run(config, out=tmp_path / "lost" / "run", execution=inline)
    assert resumed.stats.skipped == 0 and all(r.ok for r in resumed.records)
    clean = vlm_bench.run(config, out=tmp_path / "clean" / "run", execution=inline)
    assert [r.without_timing() for r in resumed.records] == [
        r.without_timing() for r in clean.records
    ]


def test_a_record_without_a_plan_is_finished_at_once() -> None:
    ep, record = _record(FAST[0])
    no_plan = record.model_copy(update={"parse": None})
    executions = Executions(InlinePool(), OPEN)
    finished = executions.submit(ep, no_plan)
    assert finished is not None and finished.execution is None and executions.in_flight == 0


def test_plain_progress_lines_every_n_episodes() -> None:
    buffer = io.StringIO()
    console = Console(file=buffer, width=200)
    with RunProgress(25, "run-x", every=10, console=console) as shown:
        shown.skipped(3)
        shown.executions_changed(4, 1, 2, 1)
        for _ in range(22):
            shown.generated(1)
            shown.written(1)
    lines = buffer.getvalue().splitlines()
    assert len(lines) == 3  # at 13 and 23 written, and the end
    assert lines[0].startswith(
        "run-x 13/25 episodes | generated 13/25 | executions 1/4 done, 2 running, 1 queued"
        " | elapsed "
    )
    assert lines[-1].startswith("run-x 25/25 episodes")
    assert "eta 0:00" in lines[-1]


def _args(cli: Cli, out: Path) -> list[str]:
    options = ("--resolution", "48", "--batch-size", "1", "--exec-workers", "2")
    return cli.run_args(out, "oracle", FAST, "0", *options)


def test_sigkill_with_parallel_executions_then_resume_equals_uninterrupted(
    cli: Cli, tmp_path: Path
) -> None:
    killed_dir = tmp_path / "killed" / "run"
    clean_dir = tmp_path / "clean" / "run"  # same folder name: same run id
    env = {k: v for k, v in os.environ.items() if k != "VLM_BENCH_SNAPSHOT_CACHE"}
    proc = subprocess.Popen(
        cli.command(*_args(cli, killed_dir)),
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    records = killed_dir / "records.jsonl"
    cli.wait_for_records(proc, records, 1, timeout=240)
    os.killpg(proc.pid, signal.SIGKILL)  # the run and its execution workers
    proc.wait()
    at_kill = len(read_records(records))
    assert 1 <= at_kill < len(FAST) * 2
    for run_dir in (killed_dir, clean_dir):
        done = cli.run(*_args(cli, run_dir), env=env, timeout=600)
        assert done.returncode == 0, done.stderr

    def outcomes(path: Path) -> list[object]:
        return [(_fields(r, "execution"), _outcome(r.execution)) for r in latest_records(path)]

    got, want = outcomes(records), outcomes(clean_dir / "records.jsonl")
    assert len(got) == len(FAST) * 2 and sorted(got, key=str) == sorted(want, key=str)
    assert len(read_records(records)) == len(FAST) * 2  # each record written once
    assert all(o[1] is not None for o in got)  # every record carries its execution


def test_ctrl_c_is_honoured_at_once_while_executions_hang(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from vlm_bench.runner import benchmark_run

    sent: list[float] = []

    def interrupt() -> None:
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    # Ctrl-C once the first execution hangs; a second one (which ends it anyway) much later.
    timers = [threading.Timer(0.5, interrupt), threading.Timer(20, interrupt)]

    class _InterruptedWhileHung(_HungPool):
        def submit(self, job: ExecutionJob) -> Future[Executed]:
            if not self.submitted:
                for timer in timers:
                    timer.start()
            return super().submit(job)

    monkeypatch.setattr(benchmark_run, "make_pool", lambda options: _InterruptedWhileHung())
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    config = RunConfig(model="oracle", tasks=FAST[:1], seeds=(0,), resolution=32)
    try:
        with pytest.raises(KeyboardInterrupt):
            vlm_bench.run(config, out=tmp_path / "run", execution=ExecutionOptions(workers=1))
        assert time.monotonic() - sent[0] < 2  # the first Ctrl-C, not the second
    finally:
        for timer in timers:
            timer.cancel()
        signal.signal(signal.SIGINT, previous)
