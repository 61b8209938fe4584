"""SFT rows are what a run sends: round 0's conversation is the request ``vlm-bench run`` builds,
and each replan row is the replan request a real closed-loop run sends after the same failed
round (same system, earlier turns, replan text, views of the state, cache key), answered by the
``rules`` planner."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

import vlm_bench.api as api
from vlm_bench.backends import Backend
from vlm_bench.backends.rules_planner import RulesBackend
from vlm_bench.episodes import get_episode
from vlm_bench.parsing import parse_plan
from vlm_bench.runner.episode_request import run_snapshots
from vlm_bench.runner.selection import EpisodeRef
from vlm_bench.training import sft_messages, target_text
from vlm_bench.training.recovery import recover
from vlm_bench.training.sft_rows import episode_examples
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.run import RunConfig

TASK = "place_on_flat_surface"  # the cube is carried in flight: a slip fails the place


class RulesRecorder(Backend):
    """Answers as ``rules`` does (in the export's answer format), sees the views, keeps every
    request."""

    name = "rules-recorder"

    def __init__(self) -> None:
        self.seen: list[GenerationRequest] = []

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        self.seen.extend(requests)
        rules = RulesBackend()
        out = []
        for r in requests:
            plan = rules.plan(r)
            assert not isinstance(plan, str), plan
            out.append(GenerationResult(id=r.id, text=target_text(plan)))
        return out


def _config() -> RunConfig:
    return RunConfig(
        model="rules-recorder",
        tasks=(TASK,),
        seeds=(0,),
        instructions=("implicit",),
        resolution=32,
        scene_as_text=True,
        loop="closed",
        max_rounds=2,
        perturb=PerturbConfig(slip=1.0),
    )


def test_plan_and_replan_rows_are_the_requests_a_closed_loop_run_sends(tmp_path: Path) -> None:
    config = _config()
    recorder = RulesRecorder()
    run = api.run(
        config, out=tmp_path / "run", backend=recorder, execution=ExecutionOptions(workers=0)
    )
    (record,) = run.records
    assert record.rounds is not None and len(record.rounds) == 2  # every slip fails the place

    episode = get_episode(TASK, 0)
    ref = EpisodeRef(TASK, 0, "implicit")
    source = run_snapshots(config, None)
    try:
        images = source.images(episode)
    finally:
        source.close()
    recovery = recover(episode, config)
    assert not recovery.recovered and len(recovery.failed) == 2
    rows = list(episode_examples(config, ref, episode, images, recovery, unrecovered=True))
    assert [r.kind for r in rows] == ["plan", "replan", "replan"]
    assert len(recorder.seen) == len(rows)
    for row, sent in zip(rows, recorder.seen, strict=True):
        answer = target_text(parse_plan(row.target, episode.object_ids()).valid_steps())
        assert row.target == answer
        assert row.messages == tuple(sft_messages(sent, row.target))
        assert row.images == tuple(p.png for p in sent.images())
    assert rows[0].target == target_text(episode.gt_plan)
    assert rows[0].prompt_hash == record.prompt_hash
    assert [r.prompt_hash for r in rows[1:]] == [r.prompt_hash for r in record.rounds]
    # a replan shows the views of the state the failed round left, not the first frame's
    assert len(rows[1].images) == len(config.views)
    assert rows[1].images != rows[0].images[: len(config.views)]
    # without ``unrecovered`` an unrecovered episode gives its plan row only
    plain = list(episode_examples(config, ref, episode, images, recovery))
    assert [r.kind for r in plain] == ["plan"]


@pytest.mark.parametrize("no_images", [False, True])
def test_messages_hold_one_image_part_per_image_in_order(no_images: bool) -> None:
    config = RunConfig(
        model="x", tasks=("standard_pick_place",), seeds=(0,), resolution=32, images=not no_images
    )
    episode = get_episode("standard_pick_place", 0)
    ref = EpisodeRef("standard_pick_place", 0, "explicit")
    source = run_snapshots(config, None)
    try:
        images = source.images(episode) if config.images else None
    finally:
        source.close()
    (row,) = episode_examples(config, ref, episode, images)
    parts = [p for m in row.messages for p in m["content"]]
    assert sum(p["type"] == "image" for p in parts) == len(row.images)
    assert len(row.images) == (0 if no_images else 4)
    assert [m["role"] for m in row.messages] == ["system", "user", "assistant"]
    assert row.messages[-1]["content"] == [{"type": "text", "text": row.target}]
    assert parse_plan(row.target, episode.object_ids()).valid_steps() == list(episode.gt_plan)
