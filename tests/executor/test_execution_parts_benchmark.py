"""``benchmarks/execution_parts.py`` still finds the functions it times (they are private names
that a refactor may move) and, against the same tree, reports equal results."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "execution_parts.py"


def _run(*args: str) -> str:
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    done = subprocess.run(
        [sys.executable, str(SCRIPT), *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


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
