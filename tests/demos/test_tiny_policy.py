"""The plain-torch policy path: a dataset read back from disk trains a tiny policy a few steps
on CPU, and the policy drives an episode's ARM steps in the closed loop, which scores it with
S_pos, S_arm, S_safe and S_task (the numbers need not be good; the path must work)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.vla.demos.lerobot_writer import EpisodeData
from vlm_bench.vla.demos.reader import DemoDataset

pytest.importorskip("torch")


@pytest.mark.smoke  # the plain-torch policy loop in the default suite
def test_a_tiny_policy_trains_from_disk_and_is_scored_in_the_closed_loop(
    synthetic: tuple[Path, list[EpisodeData]],
) -> None:
    from vlm_bench.vla.demos.tiny_policy import evaluate_policy, train_tiny_policy

    root, _ = synthetic
    policy = train_tiny_policy(DemoDataset(root), steps=40, batch_size=16, size=16, lr=5e-3)
    losses = policy.losses
    assert len(losses) == 40 and all(math.isfinite(x) for x in losses)
    assert sum(losses[-5:]) < 0.5 * sum(losses[:5])  # the action follows the state: it fits
    scores = evaluate_policy(policy, get_episode("non_prehensile_push_cube", 0), max_steps=3)
    assert scores is not None
    for value in (scores.s_pos, scores.s_arm, scores.s_safe, scores.s_task):
        assert 0.0 <= value <= 100.0
    assert scores.s_task < 100.0  # three control steps do not push the cube home
