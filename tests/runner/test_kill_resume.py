"""SIGKILL a CLI run mid-way, re-run the same command: the folder ends like an uninterrupted run."""

from __future__ import annotations

import os
import signal
import subprocess
from pathlib import Path
from typing import TYPE_CHECKING

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


def test_ctrl_c_exits_130_with_a_resume_hint(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    command = cli.command(*_args(cli, out))
    # pytest-xdist workers ignore SIGINT and children inherit that; restore the default so
    # the child Python installs its KeyboardInterrupt handler, as in a user's terminal.
    proc = subprocess.Popen(
        command,
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    records = out / "records.jsonl"
    cli.wait_for_records(proc, records, 2, timeout=50)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "re-run the same command to resume" in stderr
    assert "Traceback" not in stderr
    done = len(read_records(records))  # every line written is a complete record
    assert 2 <= done < TOTAL
    resumed = cli.run(*_args(cli, out))
    assert resumed.returncode == 0, resumed.stderr
    assert len(latest_records(records)) == TOTAL
