"""SIGKILL a closed-loop run inside round 2 of an episode, re-run the same command: the folder
ends with the records of an uninterrupted run (every round answered from the cache)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from vlm_bench.storage import latest_records

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
HOP = json.dumps([{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.1}])
TASKS = ("standard_pick_place", "tower_stacking")


def _args(cli: Cli, out: Path) -> list[str]:
    options = ("--resolution", "32", "--batch-size", "1", "--instruction", "explicit")
    loop = ("--loop", "closed", "--max-rounds", "3", "--exec-workers", "1")
    return cli.run_args(out, "mock", TASKS, "0", "-M", f"text={HOP}", *options, *loop)


def _lines(path: Path) -> int:
    return path.read_bytes().count(b"\n") if path.exists() else 0


@pytest.mark.slow
def test_sigkill_inside_round_two_then_resume_equals_uninterrupted(
    cli: Cli, tmp_path: Path
) -> None:
    killed, clean = tmp_path / "killed" / "run", tmp_path / "clean" / "run"
    env = {k: v for k, v in os.environ.items() if k != "VLM_BENCH_SNAPSHOT_CACHE"}
    proc = subprocess.Popen(
        cli.command(*_args(cli, killed)), cwd=ROOT, env=env, stderr=subprocess.DEVNULL
    )
    responses = killed / "responses.jsonl"
    # rounds 0 and 1 of both episodes, then one round-2 answer: that episode is in round 2
    deadline = 2 * len(TASKS) + 1
    while proc.poll() is None and _lines(responses) < deadline:
        time.sleep(0.005)
    assert proc.poll() is None, "the run ended before it could be stopped"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert _lines(killed / "records.jsonl") < len(TASKS)

    resumed = cli.run(*_args(cli, killed), env=env, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    done = cli.run(*_args(cli, clean), env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    got = sorted((r.without_timing() for r in latest_records(killed / "records.jsonl")), key=str)
    want = sorted((r.without_timing() for r in latest_records(clean / "records.jsonl")), key=str)
    assert len(got) == len(TASKS) and got == want
    assert all(r["loop"]["rounds_used"] == 4 for r in got)
