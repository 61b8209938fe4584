"""The Python API in a plain script (no ``if __name__ == "__main__":`` guard) with execution
workers: the workers never re-run the script, and the table equals the CLI's."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd  # type: ignore[import-untyped, unused-ignore]

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
TASKS = ("container_geometry_bowl", "slim_object_in_bowl")
"""Tasks whose GT executions take about 2 s."""

SCRIPT = """\
import vlm_bench

result = vlm_bench.run(
    model="oracle", tasks={tasks!r}, seeds=(0,), resolution=48, out={out!r},
    snapshot_cache={cache!r},
)
print("EXECUTED", result.stats.executed)
print(result.table().to_csv())
"""


def test_a_script_without_the_main_guard_gets_the_cli_table(cli: Cli, tmp_path: Path) -> None:
    cache = str(tmp_path / "snapshots")
    script = tmp_path / "plain.py"
    api_dir = tmp_path / "api" / "run"
    script.write_text(SCRIPT.format(tasks=TASKS, out=str(api_dir), cache=cache))
    done = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr and "RunLockedError" not in done.stderr
    # The script ran once: a worker that re-ran it would print (and run) again.
    assert done.stdout.count("EXECUTED") == 1
    assert f"EXECUTED {len(TASKS)}" in done.stdout

    cli_dir = tmp_path / "cli" / "run"
    ran = cli.run(
        *cli.run_args(cli_dir, "oracle", TASKS, "0", "--resolution", "48"),
        env={**os.environ, "VLM_BENCH_SNAPSHOT_CACHE": cache},
    )
    assert ran.returncode == 0, ran.stderr
    api = pd.read_csv(api_dir / "summary.csv")
    want = pd.read_csv(cli_dir / "summary.csv")
    assert not api["S_total"].isna().any() and (api["exec_success"] == 100.0).all()
    pd.testing.assert_frame_equal(api, want)
