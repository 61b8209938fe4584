"""Shared report fixtures: records built in-test, run folders written from them, real runs."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import pytest

from vlm_bench.types.execution import ExecutionSummary, FailureCode, VlaScores
from vlm_bench.types.records import EpisodeRecord, episode_key
from vlm_bench.types.run import DataHashes, RunConfig, RunManifest
from vlm_bench.types.scores import PlanScores
from vlm_bench.types.task import Suite

SUITE_OF = {
    "standard_pick_place": Suite.BASE,
    "color_distractor_green": Suite.BASE,
    "target_color_yellow": Suite.OBJECT_SPATIAL,
    "synonym_block_bin": Suite.SEMANTIC,
    "tower_stacking": Suite.LONG_HORIZON,
    "drawer_interaction": Suite.LONG_HORIZON,
}
"""Real task ids (the paper grouping maps them) with their suites."""

GT = [
    {"subtask": 0, "tasktype": "UAV", "direction": "front"},
    {"subtask": 1, "tasktype": "ARM", "object": "gray_cube", "skill": "pick"},
    {"subtask": 2, "tasktype": "ARM", "object": "yellow_basket", "skill": "place"},
]


def scores(plan: float, loc: float, obj: float, skill: float, succ: bool = False) -> PlanScores:
    """Planning scores with S_total the mean of the four (the paper's weights)."""
    return PlanScores(
        s_plan=plan, s_loc=loc, s_obj=obj, s_skill=skill,
        s_total=(plan + loc + obj + skill) / 4, succ=succ,
        m=0, k=0, n=1, n_move=0, m_obj=0, k_obj=0, n_obj=0, m_skill=0, n_skill=0,
    )  # fmt: skip


def execution(success: bool, s_task: float) -> ExecutionSummary:
    """An execution summary (failing at step 1 unless it succeeded)."""
    return ExecutionSummary(
        exec_success=success,
        steps_ok=success,
        n_steps_done=3 if success else 1,
        failure_reason=None if success else "step 1: gray_cube is out of reach",
        failure_code=None if success else FailureCode.OUT_OF_REACH,
        s_task=s_task,
        scores=VlaScores(s_pos=50.0, s_arm=50.0, s_safe=100.0, s_task=s_task, total=50.0),
        sim_time_s=1.0,
        wall_time_s=0.1,
    )


def record(
    model: str,
    task: str,
    seed: int,
    variant: str,
    total: float | None,
    *,
    succ: bool = False,
    loc: float | None = None,
    tags: Sequence[str] = (),
    tier: str = "valid",
    run: str | None = None,
    executed: ExecutionSummary | None = None,
) -> EpisodeRecord:
    """A record whose four metrics equal ``total`` (``loc`` overrides S_loc); None = error."""
    ok = total is not None
    parse = {"tier": tier, "steps": [], "errors": []}
    return EpisodeRecord(
        run_id=run or model,
        key=episode_key(task, seed, variant),
        task_id=task,
        suite=SUITE_OF[task],
        seed=seed,
        variant=variant,  # type: ignore[arg-type]
        model=model,
        gt_plan=GT,
        parse=parse if ok else None,  # type: ignore[arg-type]
        scores=scores(total, total if loc is None else loc, total, total, succ) if ok else None,
        error_tags=tuple(tags),
        status="ok" if ok else "error",
        backend_error=None if ok else "HTTP 503",
        execution=executed,
    )


def write_run(
    root: Path, records: Sequence[EpisodeRecord], model: str | None = None, **config: Any
) -> Path:
    """A run folder (manifest + records.jsonl) holding ``records``."""
    root.mkdir(parents=True, exist_ok=True)
    cfg = RunConfig(model=model or records[0].model, **config)
    manifest = RunManifest(
        run_id=root.name,
        config=cfg,
        config_hash=cfg.config_hash(),
        backend="mock",
        data=DataHashes(prompts="p", skills="s", ground_truth="g"),
        packages={},
        created="2026-01-01T00:00:00Z",  # type: ignore[arg-type]
    )
    (root / "manifest.json").write_text(manifest.model_dump_json(indent=1))
    lines = [json.dumps(r.model_dump(mode="json")) for r in records]
    (root / "records.jsonl").write_text("\n".join(lines) + "\n")
    return root


@pytest.fixture
def make_scores() -> Callable[..., PlanScores]:
    """:func:`scores`."""
    return scores


@pytest.fixture
def make_record() -> Callable[..., EpisodeRecord]:
    """:func:`record`."""
    return record


@pytest.fixture
def make_execution() -> Callable[..., ExecutionSummary]:
    """:func:`execution`."""
    return execution


@pytest.fixture
def make_run() -> Callable[..., Path]:
    """:func:`write_run`."""
    return write_run


@pytest.fixture(scope="session")
def real_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """oracle, random and mock runs over the same 8 episodes (2 tasks × seed 0-1 × 2
    instructions), planning only, 64 px views (shared snapshot cache beside them)."""
    import vlm_bench

    root = tmp_path_factory.mktemp("runs")
    tasks = ("standard_pick_place", "synonym_block_bin")
    common = {"tasks": tasks, "seeds": (0, 1), "resolution": 64, "execute": False}
    runs = {"oracle": root / "oracle", "random": root / "random"}
    for model, out in runs.items():
        vlm_bench.run(model=model, out=out, **common)
    oracle = {r.key: r for r in vlm_bench.load_run(runs["oracle"]).records}
    script = []
    for n, (key, rec) in enumerate(oracle.items()):
        plan = json.loads(rec.raw_output)
        if n % 4 == 1:  # a wrong first direction
            plan[0]["direction"] = "back" if plan[0]["direction"] != "back" else "left"
        if n % 4 == 2:
            script.append({"id": key, "text": "I cannot tell from these images."})
            continue
        if n % 4 == 3:
            script.append({"id": key, "error": "mock: server timeout"})
            continue
        script.append({"id": key, "text": json.dumps(plan)})
    outputs = root / "outputs.jsonl"
    outputs.write_text("\n".join(json.dumps(s) for s in script) + "\n")
    runs["mock"] = root / "mock"
    vlm_bench.run(model="mock", backend_args={"file": str(outputs)}, out=runs["mock"], **common)
    return runs
