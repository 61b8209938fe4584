"""``benchmarks/sweep_profile.py`` still finds the functions it charges phases to (private names a
refactor may move): an execution's CPU lands in physics, IK and collision checks, not all in
"the rest"."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "sweep_profile.py"


def test_phases_are_charged() -> None:
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    args = ["--episodes", "clear_desk_push_box:3", "--workers", "1", "--top", "5"]
    done = subprocess.run(
        [sys.executable, str(SCRIPT), *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "1/1 succeeded" in done.stdout, done.stdout
    cpu = {
        row[0]: float(row[1])
        for line in done.stdout.splitlines()
        if line.startswith("| ") and (row := line.strip("| ").split(" | "))[1][0].isdigit()
    }
    for phase in ("physics: mj_step", "physics: UAV controller", "IK solves", "collision checks"):
        assert cpu[phase] > 0, done.stdout
    assert cpu["planning logic (the rest)"] < 0.5 * sum(cpu.values()), done.stdout
    assert "mj_step" in done.stdout.split("Top 5 functions")[1], done.stdout
