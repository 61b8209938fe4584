"""A demos export leaves out a train seed whose episode repeats a test episode, and says so."""

from __future__ import annotations

from pathlib import Path

import pytest

from vlm_bench.episodes import train_split
from vlm_bench.types.episode import Episode
from vlm_bench.vla.demos.config import DemoExportConfig
from vlm_bench.vla.demos.export import REPEAT, export_demos


def test_a_train_seed_repeating_a_test_episode_is_left_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def every_one_repeats(episode: Episode, *_: object) -> int:
        return 0

    monkeypatch.setattr(train_split, "repeat_of", every_one_repeats)
    config = DemoExportConfig(tasks=("standard_pick_place",), seeds=(10, 11), size=32)
    summary = export_demos(config, tmp_path / "out")
    assert summary.failures[REPEAT] == 2
    assert summary.executions == summary.kept == summary.episodes == 0
    assert f"2 {REPEAT}" in (tmp_path / "out" / "README.md").read_text()
