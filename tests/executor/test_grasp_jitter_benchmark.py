"""``benchmarks/grasp_jitter.py``, the stand-in for another CPU's last bits: a nudged cup pick
executes, the cup held without spinning (the old cylinder collider spun it to 48 rad/s and blew
up under the same nudge: docs/decisions.md)."""

from __future__ import annotations

from tests.conftest import run_benchmark


def test_a_nudged_cup_pick_executes_without_spinning_the_cup() -> None:
    args = ["--kinds", "cup", "--tasks", "pick_left_cup_red", "--seeds", "0"]
    stdout = run_benchmark("grasp_jitter.py", *args, "--offsets", "0.3", "--workers", "1")
    assert "1 episodes pick ['cup']; 1 executions" in stdout, stdout
    assert "1/1 succeed" in stdout, stdout
    row = next(line for line in stdout.splitlines() if line.startswith("| cup |"))
    spin = float(row.split("|")[3])
    assert 0.0 < spin < 5.0, stdout
