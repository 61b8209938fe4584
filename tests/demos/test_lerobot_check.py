"""lerobot's own LeRobotDataset reads a written dataset and its ACT trains on it (slow; runs in
lerobot's environment, which ``python benchmarks/lerobot_check.py`` builds)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.demos.conftest import LENGTHS, write_synthetic

pytestmark = pytest.mark.slow
ROOT = Path(__file__).resolve().parents[2]
VENV = ROOT / ".venv-lerobot"


@pytest.mark.skipif(
    not (VENV / ".lerobot-ready").is_file(),
    reason="lerobot's environment is not built (python benchmarks/lerobot_check.py builds it)",
)
def test_lerobot_loads_the_dataset_and_trains_act(tmp_path: Path) -> None:
    root = tmp_path / "demos"
    write_synthetic(root)
    script = ROOT / "benchmarks" / "lerobot_check.py"
    cmd = [sys.executable, str(script), "--dataset", str(root), "--venv", str(VENV)]
    done = subprocess.run([*cmd, "--steps", "2"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr[-2000:] + done.stdout[-2000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert found["problems"] == [] and found["fps"] == 20
    assert found["episodes"] == len(LENGTHS) and found["frames"] == sum(LENGTHS)
    assert found["lengths"] == list(LENGTHS) and len(found["act_losses"]) == 2
