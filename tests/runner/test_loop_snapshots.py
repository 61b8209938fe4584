"""A replan started from the frozen state of the round before gives what executing every
earlier round again gives: the same execution, the same state and views, the same records."""

from __future__ import annotations

from pathlib import Path

import pytest

import vlm_bench.api as api
from tests.runner.test_closed_loop import Hopper
from vlm_bench.episodes import get_episode
from vlm_bench.executor import frozen_episode
from vlm_bench.rounds import StateView
from vlm_bench.runner.execution_jobs import ExecutionJob, execute_job
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.execution import ExecutionOptions, ExecutorConfig
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.run import RunConfig

TASK = "place_on_flat_surface"
SHOW = StateView(("overhead", "wrist"), 32, True)


def test_a_replan_from_the_snapshot_equals_one_from_re_execution() -> None:
    episode = get_episode(TASK, 0)
    plan = tuple(episode.gt_plan)
    pick = next(i for i, s in enumerate(plan) if isinstance(s, ArmStep) and s.skill == "pick")
    perturb = PerturbConfig(slip=0.5, bump=0.5)
    first = execute_job(
        ExecutionJob(TASK, 0, ExecutorConfig(perturb=perturb), (plan[: pick + 1],), SHOW)
    )
    assert first.frozen is not None and first.state is not None  # goals unmet: a replan
    rounds = (plan[: pick + 1], plan[pick + 1 :])
    again = execute_job(ExecutionJob(TASK, 0, ExecutorConfig(perturb=perturb), rounds, SHOW))
    resumed = execute_job(
        ExecutionJob(TASK, 0, ExecutorConfig(perturb=perturb), rounds, SHOW, first.frozen)
    )
    assert len(again.outcomes) == 2 and len(resumed.outcomes) == 1  # the last round only
    drop = {"wall_time_s"}
    assert resumed.outcomes[0].execution.model_dump(exclude=drop) == again.outcomes[
        1
    ].execution.model_dump(exclude=drop)
    assert resumed.outcomes[0].failed_step == again.outcomes[1].failed_step
    assert (resumed.state is None) == (again.state is None)
    assert (resumed.frozen is None) == (again.frozen is None)
    if again.state is not None and resumed.state is not None:
        assert resumed.state == again.state  # the episode now, what is held, the views' PNGs


def test_no_snapshot_where_no_replan_follows() -> None:
    plan = tuple(get_episode(TASK, 0).gt_plan)
    last = execute_job(ExecutionJob(TASK, 0, ExecutorConfig(), (plan[:1],), None))
    assert not last.outcomes[-1].execution.exec_success and last.frozen is None


def _records(out: Path) -> list[dict[str, object]]:
    config = RunConfig(
        model="hopper",
        tasks=("standard_pick_place",),
        seeds=(0,),
        instructions=("explicit", "implicit"),
        resolution=32,
        loop="closed",
        max_rounds=2,
    )
    run = api.run(config=config, out=out, backend=Hopper(), execution=ExecutionOptions(workers=0))
    return [r.without_timing() | {"run_id": None} for r in run.records]


def test_closed_loop_records_equal_with_and_without_snapshots(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    with_snapshots = _records(tmp_path / "s" / "run")
    monkeypatch.setattr(frozen_episode, "freeze", lambda live: None)  # every job re-executes
    assert _records(tmp_path / "r" / "run") == with_snapshots
