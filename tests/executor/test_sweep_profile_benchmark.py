"""``benchmarks/sweep_profile.py`` still finds the functions it charges phases to (private names a
refactor may move): an execution's CPU lands in physics, IK and collision checks, not all in
"the rest"."""

from __future__ import annotations

from tests.conftest import run_benchmark


def test_phases_are_charged() -> None:
    args = ["--episodes", "clear_desk_push_box:3", "--workers", "1", "--top", "5"]
    stdout = run_benchmark("sweep_profile.py", *args)
    assert "1/1 succeeded" in stdout, stdout
    cpu = {
        row[0]: float(row[1])
        for line in stdout.splitlines()
        if line.startswith("| ") and (row := line.strip("| ").split(" | "))[1][0].isdigit()
    }
    for phase in ("physics: mj_step", "physics: UAV controller", "IK solves", "collision checks"):
        assert cpu[phase] > 0, stdout
    assert cpu["planning logic (the rest)"] < 0.5 * sum(cpu.values()), stdout
    assert "mj_step" in stdout.split("Top 5 functions")[1], stdout
