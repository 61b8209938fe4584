"""``benchmarks/execution_parts.py`` still finds the functions it times (they are private names
that a refactor may move) and, against the same tree, reports equal results."""

from __future__ import annotations

from pathlib import Path

from tests.conftest import run_benchmark

ROOT = Path(__file__).resolve().parents[2]


def _run(*args: str) -> str:
    return run_benchmark("execution_parts.py", *args)


def test_parts_are_timed() -> None:
    out = _run("--episodes", "clear_desk_push_box:3")
    rows = {line.split(" | ")[0].lstrip("| ") for line in out.splitlines() if line.startswith("|")}
    for part in ("physics steps", "· mj_step", "· UAV controller (Python)", "IK solves"):
        assert part in rows, out
    steps = next(line for line in out.splitlines() if line.startswith("| · mj_step"))
    assert " steps |" in steps, out  # the timers counted the physics steps


def test_a_tree_against_itself_is_equal() -> None:
    out = _run("--episodes", "clear_desk_push_box:3", "--against", str(ROOT))
    assert "1/1 equal" in out, out
