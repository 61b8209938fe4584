"""A real export end to end (slow: each demonstration is a full scripted execution, rendered
every 50 ms): the CLI writes a LeRobot folder, the recorded actions replay to success in the
gym environment, one episode per ARM step splits it, and a tiny policy trains on it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vlm_bench.cli.main import main
from vlm_bench.episodes import get_episode
from vlm_bench.types.plan import ArmStep
from vlm_bench.vla.demos.reader import DemoDataset
from vlm_bench.vla.demos.replay import replay_episode

pytestmark = pytest.mark.slow
TASK = "non_prehensile_push_cube"


def _export(out: Path, *extra: str) -> None:
    args = ["export", "demos", str(out), "--task", TASK, "--seeds", "10", "--no-progress"]
    with pytest.raises(SystemExit) as done:
        main([*args, "--views", "wrist", "--size", "32", *extra])
    assert done.value.code in (0, None)


def test_an_export_replays_to_success_and_splits_by_arm_step(tmp_path: Path) -> None:
    out = tmp_path / "demos"
    _export(out)
    info = json.loads((out / "meta/info.json").read_text())
    assert info["total_episodes"] == 1 and info["fps"] == 20
    data = DemoDataset(out)
    stored = data.episode(0)
    assert stored.task.startswith("Push") and len(stored.actions) == info["total_frames"]
    assert data.images(0, "wrist").shape == (info["total_frames"], 32, 32, 3)
    replay = replay_episode(data, 0)
    assert replay.success, replay

    steps = tmp_path / "steps"
    _export(steps, "--per-arm-step")
    split = DemoDataset(steps)
    push = get_episode(TASK, 10).gt_plan[-1]
    assert isinstance(push, ArmStep)
    assert len(split) == 1 and split.episode(0).task == f"push {push.object} to {push.target}"
    assert 0 < len(split.episode(0).actions) < len(stored.actions)
    with pytest.raises(Exception, match="one ARM step"):
        replay_episode(split, 0)


def test_a_tiny_policy_trains_on_a_real_export(tmp_path: Path) -> None:
    pytest.importorskip("torch")
    from vlm_bench.vla.demos.tiny_policy import evaluate_policy, train_tiny_policy

    out = tmp_path / "demos"
    _export(out)
    policy = train_tiny_policy(DemoDataset(out), steps=10, batch_size=16, size=32)
    scores = evaluate_policy(policy, get_episode(TASK, 11), max_steps=20, render_size=32)
    assert scores is not None
    print(f"tiny policy on {TASK}/11: {scores}")
