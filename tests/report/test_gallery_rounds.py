"""The gallery shows each replan of a closed-loop episode: the views of the state at the
failure (rendered again by executing the earlier rounds), the feedback, the new plan."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import vlm_bench.api as api
from vlm_bench.backends import Backend
from vlm_bench.report.gallery import write_gallery
from vlm_bench.runner.run_views import run_views
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

HOP = json.dumps([{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.1}])


class Hopper(Backend):
    name = "hopper"

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        return [GenerationResult(id=r.id, text=HOP) for r in requests]


def test_a_replan_shows_the_state_feedback_and_plan(tmp_path: Path) -> None:
    run = tmp_path / "run"
    api.run(
        out=run,
        backend=Hopper(),
        execution=ExecutionOptions(workers=0),
        model="hopper",
        tasks=("standard_pick_place",),
        seeds=(0,),
        instructions=("explicit",),
        resolution=32,
        loop="closed",
        max_rounds=1,
    )
    page = write_gallery(run, tmp_path / "gallery", views=run_views(render=True)).read_text()
    assert "Replan 1" in page and "state at the failure" in page
    assert "every step succeeded, but the task is not complete" in page
    assert "holding: nothing" in page
    shots = sorted(p.name for p in (tmp_path / "gallery" / "img").glob("*_r1_*.jpg"))
    assert shots == [
        f"standard_pick_place_0_explicit_r1_{v}.jpg"
        for v in sorted(("uav", "wrist", "overhead", "side"))
    ]
    assert "Replan 2" not in page
