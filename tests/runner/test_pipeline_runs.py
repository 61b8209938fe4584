"""The episode pipeline through the Python API: batching, requests, errors, caches, rescore."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import pandas as pd
import pytest

import vlm_bench.api as api
from vlm_bench.backends import Backend, operational_args
from vlm_bench.backends.builtin import OracleBackend
from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.runner import SnapshotSource
from vlm_bench.storage import ConfigMismatchError, SnapshotCache, latest_records
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.run import RunConfig

TASKS = ("standard_pick_place", "tower_stacking")
# Execution is tested in test_execution_runs.py; these tests are about the planning pipeline.
SMALL = {"tasks": TASKS, "seeds": (0, 1), "resolution": 32, "execute": False}


class CountingOracle(Backend):
    """The oracle, counting calls; can fail chosen ids or raise on a chosen call."""

    name = "counting"

    def __init__(
        self,
        fail_ids: Sequence[str] = (),
        raise_on_call: int | None = None,
        raise_exc: BaseException | None = None,
    ) -> None:
        self.inner = OracleBackend()
        self.calls: list[list[GenerationRequest]] = []
        self.fail_ids = set(fail_ids)
        self.raise_on_call = raise_on_call
        self.raise_exc = raise_exc or RuntimeError("driver crashed")

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        self.calls.append(list(requests))
        if self.raise_on_call == len(self.calls):
            raise self.raise_exc
        out = self.inner.generate(requests, config)
        return [
            GenerationResult(id=r.id, error="HTTP 500") if r.id in self.fail_ids else r for r in out
        ]

    @property
    def n_requests(self) -> int:
        return sum(len(c) for c in self.calls)


def _config(**extra: object) -> RunConfig:
    return RunConfig(model="oracle", **{**SMALL, **extra})  # type: ignore[arg-type]


def _comparable(run_dir: Path) -> list[dict[str, object]]:
    return [r.without_timing() for r in latest_records(run_dir / "records.jsonl")]


def test_requests_carry_what_the_builtins_need(tmp_path: Path) -> None:
    fake = CountingOracle()
    config = _config(
        generation=GenerationConfig(batch_size=3, constrained=True), views=("uav", "overhead")
    )
    result = api.run(config, out=tmp_path / "run", backend=fake)
    assert [len(c) for c in fake.calls] == [3, 3, 2]  # 8 episodes in batches of 3
    req = fake.calls[0][0]
    episode = get_episode("standard_pick_place", 0)
    assert req.id == req.episode_id == "standard_pick_place/0/explicit"
    assert req.meta is not None and req.meta.gt_plan == episode.gt_plan
    assert req.meta.object_ids == tuple(episode.object_ids())
    assert [img.view for img in req.images()] == ["uav", "overhead"]
    assert all(img.png.startswith(b"\x89PNG") for img in req.images())
    assert req.json_schema is not None and req.json_schema["type"] == "array"
    assert result.manifest.backend == "counting"
    assert all(r.scores is not None and r.scores.succ for r in result.records)


def test_no_schema_without_constrained_decoding(tmp_path: Path) -> None:
    fake = CountingOracle()
    api.run(_config(tasks=TASKS[:1], seeds=(0,)), out=tmp_path / "run", backend=fake)
    assert all(r.json_schema is None for call in fake.calls for r in call)


def test_backend_errors_are_recorded_then_retried_on_resume(tmp_path: Path) -> None:
    failing = {"standard_pick_place/1/implicit", "tower_stacking/0/explicit"}
    first = api.run(_config(), out=tmp_path / "run", backend=CountingOracle(fail_ids=failing))
    errors = {r.key for r in first.records if not r.ok}
    assert errors == failing and first.stats.errors == 2
    assert all(
        r.backend_error == "HTTP 500" and r.scores is None for r in first.records if not r.ok
    )
    row = first.summary[(first.summary.instruction == "both") & (first.summary.suite == "overall")]
    assert int(row.n_error.iloc[0]) == 2
    second_backend = CountingOracle()
    second = api.run(_config(), out=tmp_path / "run", backend=second_backend)
    assert sorted(r.id for c in second_backend.calls for r in c) == sorted(failing)
    assert all(r.ok for r in second.records) and second.stats.skipped == 6
    lines = (tmp_path / "run" / "records.jsonl").read_text().splitlines()
    assert len(lines) == 10  # append-only: the error records stay, the retries follow


def test_a_resume_with_a_longer_timeout_continues_the_run(tmp_path: Path) -> None:
    # The natural fix after timeouts: more time and gentler retries, same run folder.
    args = {"base_url": "http://127.0.0.1:9/v1", "timeout_s": "10", "backoff_s": "1"}
    first = _config().model_copy(update={"model": "openai/served", "backend_args": args})
    timed_out = {"tower_stacking/0/explicit"}
    out = tmp_path / "run"
    api.run(first, out=out, backend=CountingOracle(fail_ids=timed_out))
    longer = first.model_copy(
        update={"backend_args": {**args, "timeout_s": "600", "backoff_s": "5", "retries": "9"}}
    )
    assert api.run_dir_for(longer) == api.run_dir_for(first)
    retry = CountingOracle()
    resumed = api.run(longer, out=out, backend=retry)
    assert [r.id for c in retry.calls for r in c] == sorted(timed_out)
    assert all(r.ok for r in resumed.records) and resumed.stats.skipped == 7
    # An argument that can change the answers still makes another run.
    other = first.model_copy(update={"backend_args": {**args, "image_detail": "low"}})
    with pytest.raises(ConfigMismatchError, match=r"backend_args\.image_detail"):
        api.run(other, out=out, backend=CountingOracle())


def test_each_backend_declares_its_operational_arguments() -> None:
    assert operational_args("openai/x") == {
        "concurrency",
        "timeout_s",
        "retries",
        "backoff_s",
        "backoff_max_s",
        "check_server",
        "check_timeout_s",
    }
    assert operational_args("Qwen/Qwen2.5-VL-3B-Instruct") == {"device_map"}  # hf
    assert operational_args("vllm/x") == operational_args("oracle") == frozenset()


def test_a_raising_backend_does_not_kill_the_run(tmp_path: Path) -> None:
    fake = CountingOracle(raise_on_call=1)
    result = api.run(
        _config(generation=GenerationConfig(batch_size=4)), out=tmp_path / "run", backend=fake
    )
    assert len(fake.calls) == 2
    bad = [r for r in result.records if not r.ok]
    assert len(bad) == 4 and all(
        "RuntimeError: driver crashed" in (r.backend_error or "") for r in bad
    )


def test_interrupt_leaves_a_resumable_folder(tmp_path: Path) -> None:
    config = _config(generation=GenerationConfig(batch_size=2))
    fake = CountingOracle(raise_on_call=3, raise_exc=KeyboardInterrupt())
    with pytest.raises(KeyboardInterrupt):
        api.run(config, out=tmp_path / "run", backend=fake)
    assert len(latest_records(tmp_path / "run" / "records.jsonl")) == 4
    resumed = CountingOracle()
    api.run(config, out=tmp_path / "run", backend=resumed)
    assert resumed.n_requests == 4
    api.run(config, out=tmp_path / "clean" / "run", backend=CountingOracle())
    assert _comparable(tmp_path / "run") == _comparable(tmp_path / "clean" / "run")


def test_response_cache_answers_episodes_whose_records_were_lost(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    api.run(_config(), out=run_dir, backend=CountingOracle())
    before = _comparable(run_dir)
    lines = (run_dir / "records.jsonl").read_text().splitlines(keepends=True)
    (run_dir / "records.jsonl").write_text("".join(lines[:3]))  # responses cached, records lost
    fake = CountingOracle()
    result = api.run(_config(), out=run_dir, backend=fake)
    assert fake.calls == [] and result.stats.cached == 5
    assert _comparable(run_dir) == before


def test_rescore_recomputes_without_the_backend(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    fake = CountingOracle()
    api.run(_config(), out=run_dir, backend=fake)
    calls = len(fake.calls)
    before = _comparable(run_dir)
    # Damage the stored scores: rescore must recompute them, not copy them.
    damaged = []
    for line in (run_dir / "records.jsonl").read_text().splitlines():
        row = json.loads(line)
        row["scores"]["s_total"], row["scores"]["succ"], row["error_tags"] = 1.0, False, ["x"]
        damaged.append(json.dumps(row))
    (run_dir / "records.jsonl").write_text("\n".join(damaged) + "\n")
    result = api.rescore(run_dir)
    assert len(fake.calls) == calls and result.stats.changed == 8
    assert _comparable(run_dir) == before
    summary = pd.read_csv(run_dir / "summary.csv")
    assert set(summary["Succ"]) == {100.0}  # a percentage of episodes, not a fraction


def test_finished_resume_never_builds_the_backend(tmp_path: Path) -> None:
    api.run(_config(tasks=TASKS[:1], seeds=(0,)), out=tmp_path / "run")
    again = api.run(
        _config(tasks=TASKS[:1], seeds=(0,), backend_args={}), out=tmp_path / "run", backend=None
    )
    assert again.stats.generate_calls == 0 and again.stats.skipped == 2


def test_snapshot_cache_is_shared_and_per_view(tmp_path: Path) -> None:
    cache = SnapshotCache(tmp_path / "snap")
    episode = get_episode("standard_pick_place", 1)
    first = SnapshotSource(("uav", "side"), 32, cache=cache)
    images = first.images(episode)
    first.close()
    assert first.rendered == 1 and set(images) == {"uav", "side"}
    second = SnapshotSource(("side",), 32, cache=cache)
    assert second.images(episode) == {"side": images["side"]} and second.rendered == 0
    third = SnapshotSource(("side", "wrist"), 32, cache=cache)
    assert third.images(episode)["side"] == images["side"] and third.rendered == 1
    third.close()
    other_size = SnapshotSource(("side",), 48, cache=cache)
    other_size.images(episode)
    other_size.close()
    assert other_size.rendered == 1


def test_run_options_are_checked_before_anything_is_written(tmp_path: Path) -> None:
    with pytest.raises(UnknownNameError, match="unknown task 'no_such_task'"):
        api.run(model="oracle", tasks=("no_such_task",), out=tmp_path / "a")
    with pytest.raises(ConfigError, match="uav_noise > 0 needs execute"):
        api.run(model="oracle", execute=False, uav_noise=1.0, out=tmp_path / "b")
    with pytest.raises(ConfigError, match="uav_noise"):
        api.run(model="oracle", uav_noise=-1.0, out=tmp_path / "e")
    with pytest.raises(ConfigError, match="resolution 2048 exceeds"):
        api.run(model="oracle", resolution=2048, out=tmp_path / "d")
    with pytest.raises(ConfigError, match="give tasks or a suite, not both"):
        api.run(model="oracle", tasks=TASKS, suite="long_horizon", out=tmp_path / "c")
    assert not any(tmp_path.iterdir())


def test_gt_plan_of_records_matches_the_episode(tmp_path: Path) -> None:
    result = api.run(
        _config(tasks=TASKS[1:], seeds=(1,)), out=tmp_path / "run", backend=CountingOracle()
    )
    episode = get_episode("tower_stacking", 1)
    assert all(r.gt_plan == plan_to_json(episode.gt_plan) for r in result.records)
    assert all(r.plan == r.gt_plan for r in result.records)


class MeteredOracle(CountingOracle):
    """The oracle, reporting usage: tokens, a finish reason and latencies per answer."""

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        return [
            r.model_copy(
                update={
                    "latency_s": 0.25,
                    "batch_latency_s": 1.5,
                    "prompt_tokens": 1000 + i,
                    "completion_tokens": 40 + i,
                    "finish_reason": "length",
                }
            )
            for i, r in enumerate(super().generate(requests, config))
        ]


def test_a_backends_usage_reaches_responses_and_records_and_survives_rescore(
    tmp_path: Path,
) -> None:
    from vlm_bench.storage import read_responses
    from vlm_bench.types.records import USAGE_FIELDS, usage_of

    run_dir = tmp_path / "run"
    api.run(_config(tasks=TASKS[:1], seeds=(0,)), out=run_dir, backend=MeteredOracle())
    records = latest_records(run_dir / "records.jsonl")
    responses = read_responses(run_dir / "responses.jsonl")
    assert {r.prompt_tokens for r in records} == {1000, 1001}
    for record in records:
        usage = usage_of(record)
        assert set(usage) == set(USAGE_FIELDS) and usage["finish_reason"] == "length"
        assert usage == usage_of(responses[(record.key, record.prompt_hash)])
    (run_dir / "responses.jsonl").unlink()  # rescore falls back on the records' own copy
    api.rescore(run_dir)
    assert [usage_of(r) for r in latest_records(run_dir / "records.jsonl")] == [
        usage_of(r) for r in records
    ]
