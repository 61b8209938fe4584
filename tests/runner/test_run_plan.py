"""A run's plan: the configuration checked and resolved once, before the folder is written."""

from __future__ import annotations

import pytest

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.runner.run_plan import plan_run
from vlm_bench.types.run import RunConfig

TASKS = ("standard_pick_place", "drawer_interaction")


def test_the_plan_holds_what_the_run_reads() -> None:
    config = RunConfig(model="oracle", tasks=TASKS, seeds=(1, 0), loop="closed", max_rounds=2)
    plan = plan_run(config)
    assert [r.key for r in plan.episodes] == [
        f"{t}/{s}/{v}"
        for t in ("standard_pick_place", "drawer_interaction")
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]
    assert plan.backend.name == "oracle" and plan.loop == config.loop_config()
    assert plan.executor == config.executor_config()
    assert plan.prompts["implicit"] == config.prompt_config("implicit")
    manifest = plan.manifest("run-1")
    assert manifest.config_hash == config.config_hash() and manifest.protocol == plan.protocol
    assert manifest.backend == "oracle" and manifest.protocol.episodes == 8


def test_a_planner_that_reads_no_images_is_shown_none() -> None:
    blind = plan_run(RunConfig(model="blind", tasks=TASKS[:1], execute=False))
    assert blind.shown.views == () and blind.executor is None and blind.loop is None
    mock = {"model": "mock", "backend_args": {"text": "[]"}}  # stands in for a VLM
    seeing = plan_run(RunConfig(**mock, tasks=TASKS[:1], views=("uav",), resolution=64))
    assert seeing.shown.views == ("uav",) and seeing.shown.size == 64


def test_a_bad_configuration_is_refused_before_anything_is_built() -> None:
    with pytest.raises(UnknownNameError, match=r"unknown task 'no_such_task'; valid: "):
        plan_run(RunConfig(model="oracle", tasks=("no_such_task",)))
    with pytest.raises(ConfigError, match="offscreen buffer"):
        plan_run(RunConfig(model="oracle", resolution=4096))
    with pytest.raises(ConfigError):
        plan_run(RunConfig(model="rules", tasks=TASKS[:1]))  # rules needs the scene as text
