"""Closed-loop runs: round 0 is the open-loop record, replans continue the simulation, records
keep every round, the cache answers per round, and open-loop runs do not change."""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

import pytest

import vlm_bench.api as api
from vlm_bench.backends import Backend
from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError
from vlm_bench.executor.perturbations import parse_perturb
from vlm_bench.rounds.state import StateView
from vlm_bench.runner.evaluate import EXECUTION_LOST, EpisodeInfo, scored_record
from vlm_bench.runner.execution_jobs import execute_job
from vlm_bench.runner.executions import Executions
from vlm_bench.runner.pending_jobs import MAX_ATTEMPTS, WORKER_DIED
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.run import RunConfig, run_config
from vlm_bench.types.scores import ScoringConfig

TASK = "standard_pick_place"
HOP = json.dumps([{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.1}])
SKIP = {"run_id", "rounds", "loop"}
INLINE = ExecutionOptions(workers=0)


class Hopper(Backend):
    """Answers every round with one short climb (never completes the task); logs requests."""

    name = "hopper"

    def __init__(self, fail_id: str | None = None) -> None:
        self.seen: list[GenerationRequest] = []
        self.fail_id = fail_id

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        self.seen.extend(requests)
        return [
            GenerationResult(id=r.id, error="boom")
            if r.id == self.fail_id
            else GenerationResult(id=r.id, text=HOP)
            for r in requests
        ]


def _config(**extra: object) -> RunConfig:
    fields: dict[str, object] = {
        "model": "hopper",
        "tasks": (TASK,),
        "seeds": (0,),
        "instructions": ("explicit",),
        "resolution": 32,
        **extra,
    }
    return RunConfig(**fields)


def _round0(record: EpisodeRecord) -> dict[str, object]:
    return {k: v for k, v in record.without_timing().items() if k not in SKIP}


def test_replans_continue_the_simulation_and_every_round_is_kept(tmp_path: Path) -> None:
    backend = Hopper()
    closed = api.run(
        _config(loop="closed", max_rounds=2), out=tmp_path / "c" / "run", backend=backend
    )
    (record,) = closed.records
    assert record.rounds is not None and record.loop is not None
    assert [r.round for r in record.rounds] == [1, 2]
    assert record.loop.succ_at == (False, False, False) and record.loop.end == "max_rounds"
    assert record.loop.failure_codes == ("goal_not_met",) * 3
    assert record.loop.rounds_used == 3 and record.loop.steps_executed == 3
    ids = [r.id for r in backend.seen]
    assert ids == [f"{TASK}/0/explicit", f"{TASK}/0/explicit#r1", f"{TASK}/0/explicit#r2"]
    # the same simulation goes on, on the episode's clock
    times = [record.execution.sim_time_s] + [r.execution.sim_time_s for r in record.rounds]  # type: ignore[union-attr]
    assert times == sorted(times) and len(set(times)) == 3
    feedback = record.rounds[1].feedback
    assert [s.status for s in feedback.executed] == ["done", "done"] and feedback.incomplete
    assert backend.seen[2].meta is not None and backend.seen[2].meta.round == 2
    assert len({record.prompt_hash, *(r.prompt_hash for r in record.rounds)}) == 3

    opened = api.run(
        execution=INLINE, config=_config(), out=tmp_path / "o" / "run", backend=Hopper()
    )
    (plain,) = opened.records
    assert plain.rounds is None and plain.loop is None
    assert _round0(record) == _round0(plain)  # round 0 is the open-loop record
    line = (tmp_path / "o" / "run" / "records.jsonl").read_text()
    assert '"rounds"' not in line and '"loop"' not in line and "perturbations" not in line


def test_a_resume_answers_every_round_from_the_cache(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    api.run(
        execution=INLINE, config=_config(loop="closed", max_rounds=2), out=run_dir, backend=Hopper()
    )
    want = json.loads((run_dir / "records.jsonl").read_text())
    (run_dir / "records.jsonl").write_text("")  # killed before the record was written
    backend = Hopper()
    (record,) = api.run(
        execution=INLINE, config=_config(loop="closed", max_rounds=2), out=run_dir, backend=backend
    ).records
    assert backend.seen == []  # every round came from the response cache
    assert record.rounds is not None and all(r.cached for r in record.rounds)
    got = record.without_timing()
    want_record = EpisodeRecord.model_validate(want).without_timing()
    assert got == want_record
    with pytest.raises(ConfigError, match="rescore covers open-loop runs"):
        api.rescore(run_dir)


def test_a_failed_replan_writes_an_error_record_that_a_resume_retries(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    bad = Hopper(fail_id=f"{TASK}/0/explicit#r1")
    (record,) = api.run(
        execution=INLINE, config=_config(loop="closed", max_rounds=1), out=run_dir, backend=bad
    ).records
    assert record.status == "error" and "round 1" in (record.backend_error or "")
    (fixed,) = api.run(
        execution=INLINE, config=_config(loop="closed", max_rounds=1), out=run_dir, backend=Hopper()
    ).records
    assert fixed.ok and fixed.loop is not None and fixed.loop.rounds_used == 2


def test_loop_options_enter_the_hash_only_when_set() -> None:
    base = _config()
    assert base.config_hash() == run_config(**base.model_dump()).config_hash()
    assert "loop" not in base.hashed_fields() and "perturb" not in base.hashed_fields()
    hashes = {
        base.config_hash(),
        _config(loop="closed").config_hash(),
        _config(loop="closed", max_rounds=2).config_hash(),
        _config(perturb=PerturbConfig(slip=0.3)).config_hash(),
    }
    assert len(hashes) == 4
    with pytest.raises(ConfigError, match="need loop closed"):
        run_config(**{**base.model_dump(), "max_rounds": 5})
    with pytest.raises(ConfigError, match="needs execute"):
        run_config(**{**base.model_dump(), "loop": "closed", "execute": False})


def test_perturb_option_parsing() -> None:
    assert parse_perturb("slip=0.3,bump=0.2,gust=2") == (PerturbConfig(slip=0.3, bump=0.2), 2.0)
    assert parse_perturb("gust=1.5") == (None, 1.5)
    for bad in ("slip=2", "wind=1", "slip", "bump=x", "gust=-1"):
        with pytest.raises(ConfigError, match="--perturb"):
            parse_perturb(bad)


class _FlakyPool:
    """Runs jobs inline; the first ``breaks`` fail as if their worker process died."""

    workers = 1

    def __init__(self, breaks: int) -> None:
        self.breaks = breaks
        self.restarts = 0

    def submit(self, job: Any) -> Future[Any]:
        future: Future[Any] = Future()
        if self.breaks > 0:
            self.breaks -= 1
            future.set_exception(BrokenProcessPool("a worker died"))
        else:
            future.set_result(execute_job(job))
        return future

    def restart(self) -> None:
        self.restarts += 1

    def close(self, cancel: bool = False) -> None:
        return None


def _hop_record() -> tuple[Episode, EpisodeRecord]:
    episode = get_episode(TASK, 0)
    info = EpisodeInfo("run", f"{TASK}/0/explicit", "explicit", "hopper", "h")
    response = CachedResponse(key=info.key, prompt_hash="h", text=HOP)
    return episode, scored_record(info, episode, response, ScoringConfig())


def test_a_dead_worker_is_replaced_and_the_round_sent_again() -> None:
    episode, record = _hop_record()
    pool = _FlakyPool(breaks=1)
    config = _config(loop="closed", max_rounds=1, resolution=16)
    shown = StateView(config.views, config.resolution, config.labels)
    loops = Executions(pool, config.executor_config(), config.loop_config(), shown=shown)  # type: ignore[arg-type]
    assert loops.submit(episode, record) is None
    assert list(loops.drain()) == []  # round 0 failed its goals: waiting for the replan
    assert pool.restarts == 1 and loops.waiting == 1


def test_an_episode_whose_worker_keeps_dying_is_lost_and_retried_on_resume() -> None:
    episode, record = _hop_record()
    loop = _config(loop="closed")
    dying = Executions(_FlakyPool(breaks=MAX_ATTEMPTS), loop.executor_config(), loop.loop_config())  # type: ignore[arg-type]
    dying.submit(episode, record)
    (out,) = list(dying.drain())
    assert out.status == "error" and out.loop is None  # not a result: a resume runs it again
    assert out.backend_error is not None and out.backend_error.startswith(EXECUTION_LOST)
    assert WORKER_DIED in out.backend_error and out.error_tags == ("execution_lost",)
    assert dying.stats.lost == 1 and dying.in_flight == 0


class _HungPool(_FlakyPool):
    """A pool whose executions never finish (a hung worker, a lost node)."""

    def __init__(self) -> None:
        super().__init__(breaks=0)
        self.abandoned = 0

    def submit(self, job: Any) -> Future[Any]:
        return Future()

    def abandon(self) -> None:
        self.abandoned += 1


def test_executions_that_never_finish_are_given_up_within_the_stall_bound() -> None:
    episode, record = _hop_record()
    pool = _HungPool()
    loop = _config(loop="closed")
    loops = Executions(pool, loop.executor_config(), loop.loop_config(), stall_s=0.3)  # type: ignore[arg-type]
    loops.submit(episode, record)
    start = time.monotonic()
    out: list[EpisodeRecord] = []
    while not out and time.monotonic() - start < 5:
        out = loops.collect(block=True, timeout=0.05)
    assert time.monotonic() - start < 2
    (lost,) = out
    assert lost.status == "error" and "no execution finished for 0.3 s" in (
        lost.backend_error or ""
    )
    assert pool.abandoned == 1 and loops.in_flight == 0


def test_the_pool_driver_asks_the_model_only_through_the_function_it_is_given() -> None:
    """A replan reaches the model through ``ask_model`` alone: its answer is executed (a
    hop that does not complete the task, then an empty plan that ends the episode) and a
    failed one ends the episode as an error record naming the round."""
    from vlm_bench.runner.answers import Answer, Question
    from vlm_bench.runner.execution_pools import InlinePool
    from vlm_bench.runner.executions import ReplanAsk

    def request(key: str) -> GenerationRequest:
        return GenerationRequest(id=key, system="", user=())

    asked: list[ReplanAsk] = []
    answers = iter([HOP, "[]"])

    def ask_model(asks: Sequence[ReplanAsk]) -> list[Answer]:
        asked.extend(asks)
        out = []
        for a in asks:
            question = Question(a.key, f"r{a.replan.round}", request(a.key))
            text = next(answers)
            out.append(Answer(question, CachedResponse(key=a.key, prompt_hash="x", text=text)))
        return out

    config = _config(loop="closed", max_rounds=3)
    episode, record = _hop_record()
    loops = Executions(
        InlinePool(), config.executor_config(), config.loop_config(), ask_model=ask_model
    )
    assert loops.submit(episode, record) is None
    assert loops.collect() == [] and loops.waiting == 1  # round 0 hopped: a replan is due
    assert list(loops.replans()) == []  # round 1 hops again
    assert loops.collect() == [] and loops.waiting == 1
    (done,) = loops.replans()  # round 2 answers no plan
    assert [a.replan.round for a in asked] == [1, 2]
    assert done.loop is not None and done.loop.end == "no_plan" and done.loop.rounds_used == 3
    assert [r.prompt_hash for r in done.rounds or ()] == ["r1", "r2"]

    def failing(asks: Sequence[ReplanAsk]) -> list[Answer]:
        question = Question(asks[0].key, "h1", request(asks[0].key))
        return [Answer(question, None, error="boom", latency_s=0.5)]

    loops = Executions(
        InlinePool(), config.executor_config(), config.loop_config(), ask_model=failing
    )
    loops.submit(episode, record)
    loops.collect()
    (failed,) = loops.replans()
    assert failed.status == "error" and failed.backend_error == "round 1: boom"
    assert failed.latency_s == 0.5 and loops.in_flight == 0
