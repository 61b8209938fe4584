"""World commands through the real CLI entry point."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

from PIL import Image

if TYPE_CHECKING:
    from tests.conftest import Cli


def test_tasks_json_lists_60_tasks_per_suite(cli: Cli) -> None:
    result = cli.run("tasks", "--json")
    assert result.returncode == 0, result.stderr
    rows = json.loads(result.stdout)
    assert len(rows) == 60
    assert set(rows[0]) == {"id", "name", "suite", "environment"}
    counts: dict[str, int] = {}
    for row in rows:
        counts[row["suite"]] = counts.get(row["suite"], 0) + 1
    assert counts == {
        "base_manipulation": 20,
        "object_spatial": 15,
        "semantic_understanding": 15,
        "long_horizon": 10,
    }


def test_tasks_table_and_filter(cli: Cli) -> None:
    result = cli.run("tasks", "--suite", "lh")
    assert result.returncode == 0
    assert "10 tasks" in result.stdout and "Long-Horizon: 10" in result.stdout


def test_episode_json_has_gt_in_paper_format(cli: Cli) -> None:
    result = cli.run("episode", "drawer_interaction", "--seed", "2", "--json")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    plan = data["gt_plan"]
    assert [s["subtask"] for s in plan] == list(range(len(plan)))
    assert plan[0]["tasktype"] == "UAV" and "direction" in plan[0]
    assert {"objects", "uav_start", "instructions", "goals"} <= set(data)


def test_render_writes_four_views_and_sheet(cli: Cli, tmp_path: Path) -> None:
    result = cli.run(
        "render", "standard_pick_place", "--seed", "1", "--out", str(tmp_path), "--size", "64"
    )
    assert result.returncode == 0, result.stderr
    for name in ("uav", "wrist", "overhead", "side"):
        assert Image.open(tmp_path / f"{name}.png").size == (64, 64)
    assert Image.open(tmp_path / "sheet.png").size[0] > 128


def test_user_errors_are_one_line(cli: Cli) -> None:
    cases = [
        (("episode", "no_such_task"), "unknown task 'no_such_task'; valid:"),
        (
            ("episode", "standard_pick_place", "--seed", "abc"),
            "seed must be a non-negative integer",
        ),
        (("tasks", "--suite", "nope"), "unknown suite 'nope'; valid: base_manipulation"),
        (("tasks", "--env", "moon"), "unknown environment 'moon'; valid:"),
    ]
    for args, expected in cases:
        result = cli.run(*args)
        assert result.returncode == 2, (args, result.stderr)
        assert result.stderr.count("\n") == 1 and expected in result.stderr, result.stderr
        assert "Traceback" not in result.stderr
