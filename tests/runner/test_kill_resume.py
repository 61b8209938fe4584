"""SIGKILL a CLI run mid-way, re-run the same command: the folder ends like an uninterrupted run."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from vlm_bench.storage import latest_records, read_records

ROOT = Path(__file__).resolve().parents[2]
TASKS = (
    "standard_pick_place",
    "deformable_object_banana",
    "cylinder_manipulation",
    "target_color_yellow",
    "small_object_bolt",
    "synonym_block_bin",
    "material_tin",
    "superlative_highest",
    "color_matched_sorting",
    "tower_stacking",
)
TOTAL = len(TASKS) * 2 * 2

if TYPE_CHECKING:
    from tests.conftest import Cli


def _args(cli: Cli, out: Path) -> list[str]:
    options = ("--resolution", "48", "--batch-size", "1", "--no-execute")
    return cli.run_args(out, "oracle", TASKS, "0-1", *options)


# The default suite's SIGKILL-and-resume test is test_executions.py's, with parallel executions.
@pytest.mark.slow  # three runs of 40 episodes: about a minute on a 2-core machine
def test_sigkill_mid_run_then_resume_equals_uninterrupted(cli: Cli, tmp_path: Path) -> None:
    killed_dir = tmp_path / "killed" / "run"
    clean_dir = tmp_path / "clean" / "run"  # same folder name: same run id
    # Snapshot caches beside each run folder: the clean run renders everything itself.
    env = {k: v for k, v in os.environ.items() if k != "VLM_BENCH_SNAPSHOT_CACHE"}
    proc = subprocess.Popen(
        cli.command(*_args(cli, killed_dir)),
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    records = killed_dir / "records.jsonl"
    cli.wait_for_records(proc, records, 3, timeout=50)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    at_kill = records.read_bytes().count(b"\n")
    assert 3 <= at_kill < TOTAL, at_kill

    resumed = cli.run(*_args(cli, killed_dir), env=env)
    assert resumed.returncode == 0, resumed.stderr
    assert "resumed" in resumed.stdout
    clean = cli.run(*_args(cli, clean_dir), env=env)
    assert clean.returncode == 0, clean.stderr

    got = [r.without_timing() for r in latest_records(records)]
    want = [r.without_timing() for r in latest_records(clean_dir / "records.jsonl")]
    assert len(got) == TOTAL and got == want
    # Nothing was evaluated twice: one line per episode (a torn line, if any, was cut off).
    assert len(read_records(records)) == TOTAL
    assert records.read_bytes().endswith(b"\n")


@pytest.mark.parametrize(
    ("signum", "code", "said"),
    [
        pytest.param(signal.SIGINT, 130, "interrupted", marks=pytest.mark.smoke, id="ctrl_c"),
        pytest.param(signal.SIGTERM, 143, "terminated", id="sigterm"),
    ],
)
def test_ctrl_c_or_sigterm_exits_with_a_resume_hint(
    cli: Cli, tmp_path: Path, signum: int, code: int, said: str
) -> None:
    out = tmp_path / "run"
    args = cli.run_args(out, "oracle", TASKS[:2], "0-1", "--resolution", "32", "--no-execute")
    # pytest-xdist workers ignore SIGINT and children inherit that; restore the default so
    # the child Python installs its KeyboardInterrupt handler, as in a user's terminal.
    proc = subprocess.Popen(
        cli.command(*args, "--batch-size", "1"),
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    records = out / "records.jsonl"
    cli.wait_for_records(proc, records, 2, timeout=50)
    proc.send_signal(signum)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == code, stderr
    assert said in stderr and "re-run the same command to resume" in stderr
    assert "Traceback" not in stderr
    assert 2 <= len(read_records(records)) < 8  # complete records only
    resumed = cli.run(*args)
    assert resumed.returncode == 0, resumed.stderr
    assert len(latest_records(records)) == 8


def _children(pid: int) -> list[int]:
    """Pids whose parent is ``pid`` (from /proc)."""
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    """Running (a zombie waiting for a reaper does not count)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")
def test_sigkill_of_the_run_takes_its_execution_workers_with_it(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    options = ("--resolution", "32", "--batch-size", "1", "--exec-workers", "2")
    args = cli.run_args(out, "oracle", TASKS[:4], "0", *options)
    proc = subprocess.Popen(
        cli.command(*args), cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        deadline = time.monotonic() + 90
        workers: list[int] = []
        # The two workers start with the first two executions, beside multiprocessing's tracker.
        while len(workers) < 3 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
            workers = [p for p in _children(proc.pid) if _alive(p)]
        assert len(workers) >= 3, workers
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        end = time.monotonic() + 5
        while time.monotonic() < end and any(_alive(p) for p in workers):
            time.sleep(0.1)
        assert not [p for p in workers if _alive(p)]
    finally:
        if proc.poll() is None:
            proc.kill()


@pytest.mark.slow  # two runs with executions: over a minute on a 2-core machine
@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")
def test_sigterm_stops_an_executing_run_like_ctrl_c(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "stopped" / "run"
    clean_dir = tmp_path / "clean" / "run"
    options = ("--resolution", "32", "--batch-size", "1", "--exec-workers", "2")
    args = cli.run_args(out, "oracle", TASKS[:3], "0", *options)
    proc = subprocess.Popen(
        cli.command(*args), cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    workers: list[int] = []
    deadline = time.monotonic() + 90
    while len(workers) < 3 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
        workers = [p for p in _children(proc.pid) if _alive(p)]
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 143, stderr
    assert "terminated" in stderr and "re-run the same command to resume" in stderr
    assert "Traceback" not in stderr
    end = time.monotonic() + 5
    while time.monotonic() < end and any(_alive(p) for p in workers):
        time.sleep(0.1)
    assert len(workers) >= 3 and not [p for p in workers if _alive(p)]
    records = out / "records.jsonl"
    assert len(read_records(records)) < 6  # stopped before the end
    resumed = cli.run(*args)
    assert resumed.returncode == 0, resumed.stderr
    clean = cli.run(*cli.run_args(clean_dir, "oracle", TASKS[:3], "0", *options))
    assert clean.returncode == 0, clean.stderr
    got = sorted((r.without_timing() for r in latest_records(records)), key=lambda r: r["key"])
    want = sorted(
        (r.without_timing() for r in latest_records(clean_dir / "records.jsonl")),
        key=lambda r: r["key"],
    )
    assert len(got) == 6 and got == want
