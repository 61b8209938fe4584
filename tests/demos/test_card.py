"""The dataset card says what the export holds, and says so loudly when test seeds are in it."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from vlm_bench.vla.demos import DemoExportConfig, DemoExportSummary
from vlm_bench.vla.demos.card import demos_card

DONE = DemoExportSummary(Path("x"), 3, 2, 2, 900, Counter({"grasp_failed": 1}))


def test_a_train_export_says_train_seeds_only() -> None:
    card = demos_card(DemoExportConfig(seeds=tuple(range(10, 60))), DONE, ["a", "b"])
    assert card.startswith("---\n") and "- LeRobot" in card
    assert "Train seeds only" in card and "Seeds: 10 to 59 (50)" in card
    assert "kept (successful): 2; left out: 1 grasp_failed" in card


def test_test_seeds_are_named_in_the_card() -> None:
    config = DemoExportConfig(seeds=(3, 10), allow_test_seeds=True)
    card = demos_card(config, DONE, ["a"])
    assert "**Includes test seeds 3**" in card and "Train seeds only" not in card
