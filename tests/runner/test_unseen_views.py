"""A planner that reads no images (``sees_images`` False: the text planners) gets no views: a
run renders neither the episodes' first views nor the views of failed rounds, and its records
and prompt hashes are those of the same run with every view rendered."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

import vlm_bench.api as api
from vlm_bench.backends import Backend
from vlm_bench.backends.preflight import check_backend
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.run import RunConfig

# Rounds that never complete the task: every replan renders the state a round left.
HOP = '[{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.1}]'
INLINE = ExecutionOptions(workers=0)


class Climber(Backend):
    """Answers every round with one short climb; keeps the requests it got."""

    name = "climber"

    def __init__(self) -> None:
        self.seen: list[GenerationRequest] = []

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        self.seen.extend(requests)
        return [GenerationResult(id=r.id, text=HOP) for r in requests]


class TextClimber(Climber):
    sees_images = False


def _config() -> RunConfig:
    return RunConfig(
        model="climber",
        tasks=("standard_pick_place",),
        seeds=(0,),
        instructions=("explicit",),
        resolution=32,
        loop="closed",
        max_rounds=1,
    )


def _no_rendering(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("a view was rendered")

    monkeypatch.setattr("vlm_bench.runner.cached_snapshots.SnapshotSource._render", refuse)
    monkeypatch.setattr("vlm_bench.executor.live_state.render_scene", refuse)


def test_a_text_planners_closed_loop_renders_no_views_and_records_the_same(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    seeing = Climber()
    shown = api.run(_config(), out=tmp_path / "a" / "run", backend=seeing, execution=INLINE)
    assert all(r.images() for r in seeing.seen)
    _no_rendering(monkeypatch)
    text = TextClimber()
    blind = api.run(_config(), out=tmp_path / "b" / "run", backend=text, execution=INLINE)
    assert [r.id for r in text.seen] == [r.id for r in seeing.seen]
    assert all(r.images() == [] for r in text.seen)
    assert len(text.seen) == 2  # round 0 and a replan
    (a,), (b,) = shown.records, blind.records
    assert a.rounds is not None and b.rounds is not None and len(b.rounds) == 1
    assert [r.prompt_hash for r in a.rounds] == [r.prompt_hash for r in b.rounds]
    skip = {"run_id"}
    assert {k: v for k, v in a.without_timing().items() if k not in skip} == {
        k: v for k, v in b.without_timing().items() if k not in skip
    }
    assert not list((tmp_path / "b" / ".snapshots").rglob("*.png"))


@pytest.mark.parametrize("model", ["oracle", "random", "blind", "rules"])
def test_the_builtin_text_planners_read_no_images(model: str) -> None:
    assert check_backend(model).sees_images is False


def test_a_scripted_mock_stands_in_for_a_vlm_and_gets_the_views() -> None:
    assert check_backend("mock", {"text": "[]"}).sees_images is True
