"""Plan execution inside runs: records carry execution summaries, gusts, crashes, rescore."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path

import pandas as pd
import pytest

import vlm_bench.api as api
from vlm_bench.backends import Backend
from vlm_bench.episodes import get_episode
from vlm_bench.executor import execute_plan
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.report import EXEC_VALUES, SUMMARY_COLUMNS
from vlm_bench.runner import PlanExecutor, episode_noise_seed, record_plan
from vlm_bench.runner.plan_executor import CRASH_PREFIX
from vlm_bench.storage import ConfigMismatchError, latest_records
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.execution import (
    ExecutionOptions,
    ExecutionSummary,
    ExecutorConfig,
    FailureCode,
)
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.plan import Direction, UavStep
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunConfig

TASK = "standard_pick_place"
# A short UAV-only plan (about 3 simulated seconds): fast, and its outcome does not depend on
# the ARM skills, which are still being improved.
HOP = json.dumps([{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.2}])
REFUSAL = "I cannot plan this task."


class Scripted(Backend):
    """Answers explicit requests with ``explicit`` and implicit ones with ``implicit``."""

    name = "scripted"

    def __init__(self, explicit: str = HOP, implicit: str = REFUSAL) -> None:
        self.answers = {"explicit": explicit, "implicit": implicit}

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        return [
            GenerationResult(id=r.id, text=self.answers[r.id.rsplit("/", 1)[1]]) for r in requests
        ]


def _config(**extra: object) -> RunConfig:
    fields: dict[str, object] = {
        "model": "scripted",
        "tasks": (TASK,),
        "seeds": (0,),
        "resolution": 32,
        **extra,
    }
    return RunConfig(**fields)  # type: ignore[arg-type]


def _row(summary: pd.DataFrame, instruction: str, suite: str = "overall") -> pd.Series:
    hit = summary[(summary.instruction == instruction) & (summary.suite == suite)]
    assert len(hit) == 1, summary
    return hit.iloc[0]


def test_run_records_executions_and_summary_columns(tmp_path: Path) -> None:
    result = api.run(_config(), out=tmp_path / "run", backend=Scripted())
    by_variant = {r.variant: r for r in result.records}
    hop, refusal = by_variant["explicit"], by_variant["implicit"]
    assert isinstance(hop.execution, ExecutionSummary)
    assert hop.execution.n_steps_done == 1 and hop.execution.steps_ok
    assert hop.execution.sim_time_s > 1.0 and not hop.execution.exec_success
    assert refusal.ok and refusal.execution is None  # no plan: not executed
    assert result.stats.executed == 1 and result.stats.exec_crashes == 0
    stored = latest_records(tmp_path / "run" / "records.jsonl")  # in the order executions ended
    assert {r.key: r.execution for r in stored} == {r.key: r.execution for r in result.records}

    summary = pd.read_csv(tmp_path / "run" / "summary.csv")
    assert list(summary.columns) == [
        *SUMMARY_COLUMNS[:-3],
        *EXEC_VALUES,
        "n",
        "n_error",
        "n_executed",
        "missing_groups",
        "protocol",
    ]
    explicit, implicit = _row(summary, "explicit"), _row(summary, "implicit")
    assert explicit.exec_success == 100.0 * hop.execution.exec_success
    assert explicit.S_task == pytest.approx(hop.execution.s_task)
    scores = hop.execution.scores
    assert scores is not None and explicit.S_safe == pytest.approx(scores.s_safe, abs=1e-3)
    assert explicit.VLA_total == pytest.approx(scores.total, abs=1e-3)
    # The unexecuted refusal counts 0 in every execution column.
    assert (implicit[list(EXEC_VALUES)] == 0.0).all()
    both = _row(summary, "both")
    assert both.S_safe == pytest.approx(scores.s_safe / 2, abs=1e-3)
    markdown = (tmp_path / "run" / "summary.md").read_text()
    assert "Exec" in markdown and "Task" in markdown and "S_pos" in markdown  # legend


def test_no_execute_keeps_todays_records_and_columns(tmp_path: Path) -> None:
    result = api.run(_config(execute=False), out=tmp_path / "run", backend=Scripted())
    assert all(r.execution is None for r in result.records)
    assert result.stats.executed == 0
    summary = pd.read_csv(tmp_path / "run" / "summary.csv")
    assert list(summary.columns) == [*SUMMARY_COLUMNS, "protocol"]
    assert "Exec" not in (tmp_path / "run" / "summary.md").read_text()
    assert "exec_success" not in result.summary.columns


def test_resume_refuses_another_uav_noise_or_execute(tmp_path: Path) -> None:
    quiet = Scripted(explicit=REFUSAL)  # nothing to execute: the refusals are what matters
    api.run(_config(), out=tmp_path / "run", backend=quiet)
    with pytest.raises(ConfigMismatchError, match=r"differs: uav_noise\)"):
        api.run(_config(uav_noise=1.5), out=tmp_path / "run", backend=quiet)
    with pytest.raises(ConfigMismatchError, match=r"differs: execute\)"):
        api.run(_config(execute=False), out=tmp_path / "run", backend=quiet)
    again = api.run(_config(), out=tmp_path / "run", backend=quiet)
    assert again.stats.skipped == 2


def test_an_executor_exception_is_a_recorded_failure(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def explode(*args: object, **kwargs: object) -> None:
        raise RuntimeError("boom")

    monkeypatch.setattr(LiveEpisode, "execute", explode)
    inline = ExecutionOptions(workers=0)  # the patch lives in this process only
    result = api.run(_config(), out=tmp_path / "run", backend=Scripted(), execution=inline)
    hop = next(r for r in result.records if r.variant == "explicit")
    assert hop.ok and hop.execution is not None and not hop.execution.exec_success
    assert hop.execution.failure_reason == f"{CRASH_PREFIX} RuntimeError: boom"
    assert hop.execution.failure_code is FailureCode.EXECUTOR_CRASH
    assert result.stats.exec_crashes == 1 and len(result.records) == 2
    assert _row(result.summary, "explicit").exec_success == 0.0


def test_a_non_finite_execution_number_is_a_recorded_crash(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A NaN or infinity from the simulator never reaches a record (JSON has no form for it, and
    pydantic would write null, which the record could not be read back from): the execution is a
    recorded executor crash naming the field, and the run folder reads back."""
    real = LiveEpisode.execute

    def blown_up(*args: object, **kwargs: object) -> object:
        return real(*args, **kwargs).model_copy(update={"sim_time_s": math.inf})  # type: ignore[arg-type]

    monkeypatch.setattr(LiveEpisode, "execute", blown_up)
    inline = ExecutionOptions(workers=0)  # the patch lives in this process only
    result = api.run(_config(), out=tmp_path / "run", backend=Scripted(), execution=inline)
    hop = next(r for r in result.records if r.variant == "explicit")
    assert hop.execution is not None and hop.execution.failure_code is FailureCode.EXECUTOR_CRASH
    assert "sim_time_s" in (hop.execution.failure_reason or "")
    assert "finite" in (hop.execution.failure_reason or "")
    back = sorted(r.key for r in latest_records(tmp_path / "run" / "records.jsonl"))
    assert back == sorted(r.key for r in result.records)
    with pytest.raises(ValueError, match="finite"):
        ExecutionSummary(
            exec_success=True, steps_ok=True, n_steps_done=1, s_task=100.0,
            sim_time_s=1.0, wall_time_s=1.0, displacement_total=math.nan,
        )  # fmt: skip


def test_rescore_executes_again(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    api.run(_config(), out=run_dir, backend=Scripted())
    before = [r.without_timing() for r in latest_records(run_dir / "records.jsonl")]
    damaged = []
    for line in (run_dir / "records.jsonl").read_text().splitlines():
        row = json.loads(line)
        if row["execution"] is not None:
            row["execution"].update(exec_success=True, failure_reason=None, s_task=100.0)
        damaged.append(json.dumps(row))
    (run_dir / "records.jsonl").write_text("\n".join(damaged) + "\n")
    result = api.rescore(run_dir)
    assert result.stats.changed == 1 and result.stats.executed == 1
    assert [r.without_timing() for r in latest_records(run_dir / "records.jsonl")] == before


def test_rescore_in_a_pool_keeps_the_records_and_their_order(tmp_path: Path) -> None:
    """Rescoring executes plans in worker processes (identical plans once) and writes the
    records back in the order the run wrote them, equal to an inline rescore's."""
    both = Scripted(implicit=HOP)  # both variants answer the same plan: one execution per episode
    config = _config(seeds=(0, 1))
    api.run(config, out=tmp_path / "a", backend=both, execution=ExecutionOptions(workers=0))
    order = [r.key for r in latest_records(tmp_path / "a" / "records.jsonl")]
    inline = api.rescore(tmp_path / "a", execution=ExecutionOptions(workers=0))
    api.run(config, out=tmp_path / "b", backend=both, execution=ExecutionOptions(workers=0))
    pooled = api.rescore(tmp_path / "b", execution=ExecutionOptions(workers=2))
    assert [r.key for r in latest_records(tmp_path / "b" / "records.jsonl")] == order
    assert pooled.stats.executed == 2 and inline.stats.executed == 2
    assert [r.execution for r in pooled.records] != [None] * 4
    drop = {"wall_time_s"}
    assert [r.execution.model_dump(exclude=drop) for r in pooled.records if r.execution] == [
        r.execution.model_dump(exclude=drop) for r in inline.records if r.execution
    ]


def test_scene_copies_execute_exactly_like_fresh_scenes() -> None:
    episode = get_episode(TASK, 1)
    plan = [UavStep(direction=Direction.UP, distance=0.2)]
    executor = PlanExecutor(ExecutorConfig(uav_noise=2.0))
    config = executor.config
    fresh = execute_plan(episode, plan, config)
    first = execute_plan(episode, plan, config, executor.scene(episode))
    second = execute_plan(episode, plan, config, executor.scene(episode))
    drop = {"wall_time_s"}
    assert fresh.model_dump(exclude=drop) == first.model_dump(exclude=drop)
    assert first.model_dump(exclude=drop) == second.model_dump(exclude=drop)
    calm = execute_plan(episode, plan, ExecutorConfig())
    assert calm.final_uav_pose != fresh.final_uav_pose  # the gusts act


def test_noise_seed_is_per_episode() -> None:
    seeds = {episode_noise_seed(t, s) for t in (TASK, "tower_stacking") for s in range(5)}
    assert len(seeds) == 10
    assert episode_noise_seed(TASK, 3) == episode_noise_seed(TASK, 3)
    config = _config(uav_noise=2.0).executor_config()  # one config for the whole run
    assert config.gust_seed(TASK, 3) == episode_noise_seed(TASK, 3)
    assert ExecutorConfig(noise_seed=7).gust_seed(TASK, 3) == 7  # a fixed seed where set


def test_a_runs_executor_config_holds_its_gusts_and_perturbations() -> None:
    perturb = PerturbConfig(slip=0.3)
    config = _config(uav_noise=2.0, perturb=perturb).executor_config()
    assert config.uav_noise == 2.0 and config.perturb == perturb
    assert config == ExecutorConfig(uav_noise=2.0, perturb=perturb)
    assert _config().executor_config() == ExecutorConfig()  # calm, unperturbed: the default


def test_only_usable_nonempty_plans_are_executed() -> None:
    from vlm_bench.runner.evaluate import EpisodeInfo, scored_record
    from vlm_bench.types.records import CachedResponse
    from vlm_bench.types.scores import ScoringConfig

    episode = get_episode(TASK, 0)
    info = EpisodeInfo("r", f"{TASK}/0/explicit", "explicit", "m", "h")

    def record(text: str) -> EpisodeRecord:
        response = CachedResponse(key=info.key, prompt_hash="h", text=text)
        return scored_record(info, episode, response, ScoringConfig())

    assert record_plan(record(REFUSAL)) is None
    assert record_plan(record("[]")) is None
    assert record_plan(record('[{"tasktype": "ARM", "skill": "fly"}]')) is None  # all invalid
    steps = record_plan(record(HOP))
    assert steps == [UavStep(direction=Direction.UP, distance=0.2)]
    failed = record(HOP).model_copy(update={"status": "error"})
    assert record_plan(failed) is None


def test_an_executor_executes_each_plan_on_a_fresh_copy_of_the_episodes_scene() -> None:
    from vlm_bench.types.plan import ArmStep

    episode = get_episode(TASK, 0)
    executor = PlanExecutor()
    plan: list[UavStep | ArmStep] = [UavStep(direction=Direction.UP, distance=0.1)]
    first, crash = executor.execute(episode, plan)
    again, _ = executor.execute(episode, list(plan))
    drop = {"wall_time_s"}
    assert crash is None and again.model_dump(exclude=drop) == first.model_dump(exclude=drop)
    other, _ = executor.execute(episode, [UavStep(direction=Direction.DOWN, distance=0.1)])
    assert executor.executed == 3 and other.n_steps_done == 1
