"""The ``execute`` command, videos, and ``run`` with execution and gusts, end to end."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import pytest
from PIL import Image, ImageSequence

from vlm_bench.errors import VlmBenchError
from vlm_bench.storage import latest_records
from vlm_bench.types.execution import ExecutionResult

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
TASK = "standard_pick_place"
HOP = [{"subtask": 0, "tasktype": "UAV", "direction": "up", "distance": 0.2}]
TWO_MOVES = [
    {"subtask": 0, "tasktype": "UAV", "direction": "front", "distance": 0.3},
    *[{**HOP[0], "subtask": 1}],
]


def _plan_file(tmp_path: Path, plan: object, name: str = "plan.json") -> Path:
    path = tmp_path / name
    path.write_text(plan if isinstance(plan, str) else json.dumps(plan))
    return path


def test_execute_a_hand_written_plan(cli: Cli, tmp_path: Path) -> None:
    plan = _plan_file(tmp_path, TWO_MOVES)
    printed = cli.invoke("execute", TASK, "--seed", "0", "--plan", str(plan))
    assert "move front 0.3 m" in printed and "move up 0.2 m" in printed
    assert "plan.json (2 steps)" in printed and "goals:" in printed
    assert "exec_success: no" in printed and "S_task=0.0" in printed and "S_safe=" in printed
    data = json.loads(cli.invoke("execute", TASK, "--plan", str(plan), "--json"))
    result = ExecutionResult.model_validate(data)
    assert [s.status for s in result.steps] == ["ok", "ok"] and result.steps_ok
    assert not result.exec_success and result.failure_reason is not None


def _user_error(cli: Cli, *args: str) -> str:
    """The one-line message of the VlmBenchError a command raises (in-process: fast)."""
    result = cli.result(*args)
    assert isinstance(result.exception, VlmBenchError), result.output
    message = str(result.exception)
    assert "\n" not in message
    return message


def test_invalid_plan_files_are_one_line_errors(cli: Cli, tmp_path: Path) -> None:
    # The real entry point once: exit code 2, one line on stderr, no traceback.
    prose = _plan_file(tmp_path, "I would fly to the table.", "prose.txt")
    bad = cli.run("execute", TASK, "--plan", str(prose))
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1, bad.stderr
    assert bad.stderr.startswith("error: prose.txt: no plan"), bad.stderr
    cases = {
        "skill.json": (
            [{"tasktype": "ARM", "object": "gray_cube", "skill": "teleport"}],
            "skill.json: step 0 is invalid (unknown_skill)",
        ),
        "empty.json": ([], "empty.json: no plan"),
    }
    for name, (content, message) in cases.items():
        plan = _plan_file(tmp_path, content, name)
        assert message in _user_error(cli, "execute", TASK, "--plan", str(plan))
    missing = _user_error(cli, "execute", TASK, "--plan", str(tmp_path / "nope.json"))
    assert "cannot read plan file" in missing
    hop = str(_plan_file(tmp_path, HOP))
    video = ["--video", str(tmp_path / "v.gif"), "--size", "32"]
    camera = _user_error(cli, "execute", TASK, "--plan", hop, *video, "--camera", "top")
    assert "unknown camera 'top'" in camera
    suffix = _user_error(cli, "execute", TASK, "--video", str(tmp_path / "v.avi"))
    assert "unknown video format '.avi'" in suffix
    fps = _user_error(cli, "execute", TASK, "--plan", hop, *video, "--fps", "50")
    assert "fps must be in (0, 20]" in fps


def _gif_frames(path: Path) -> list[Image.Image]:
    with Image.open(path) as gif:
        return [frame.convert("RGB") for frame in ImageSequence.Iterator(gif)]


def test_video_gif_has_frames_of_the_flight(cli: Cli, tmp_path: Path) -> None:
    gif = tmp_path / "hop.gif"
    printed = cli.invoke(
        "execute",
        TASK,
        "--plan",
        str(_plan_file(tmp_path, HOP)),
        "--video",
        str(gif),
        "--camera",
        "side",
        "--size",
        "48",
        "--fps",
        "5",
        "--no-shadows",
    )
    frames = _gif_frames(gif)
    # ~3 s of flight and hold plus 1 s settling at 5 fps, and the start frame.
    assert 10 <= len(frames) <= 40 and f"({len(frames)} frames)" in printed
    assert all(f.size == (48, 48) for f in frames)
    assert frames[0].tobytes() != frames[-1].tobytes()  # the UAV climbed


def test_video_mp4(cli: Cli, tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg")
    import imageio.v2 as imageio

    mp4 = tmp_path / "hop.mp4"
    cli.invoke(
        "execute",
        TASK,
        "--plan",
        str(_plan_file(tmp_path, HOP)),
        "--video",
        str(mp4),
        "--camera",
        "overhead",
        "--size",
        "64",
        "--fps",
        "10",
        "--no-shadows",
    )
    reader = imageio.get_reader(str(mp4))
    try:
        frames = list(reader.iter_data())  # list(reader) asks len(): inf for ffmpeg
        assert reader.get_meta_data()["fps"] == 10.0
    finally:
        reader.close()
    assert len(frames) > 10 and frames[0].shape == (64, 64, 3)


def test_run_executes_by_default_and_refuses_other_gusts(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    args = [
        "run",
        "--model",
        "mock",
        "-M",
        f"text={json.dumps(HOP)}",
        "--task",
        TASK,
        "--seeds",
        "0",
        "--instruction",
        "explicit",
        "--resolution",
        "32",
        "--no-progress",
    ]
    printed = cli.invoke(*args, "--out", str(out))
    assert "1 plan(s) executed" in printed and "Exec" in printed
    (record,) = latest_records(out / "records.jsonl")
    assert record.execution is not None and record.execution.steps_ok
    summary = pd.read_csv(out / "summary.csv")
    assert {"exec_success", "S_task", "S_pos", "S_arm", "S_safe", "VLA_total"} <= set(
        summary.columns
    )
    refused = cli.run(*args, "--out", str(out), "--uav-noise", "1.5")
    assert refused.returncode == 2 and "differs: uav_noise" in refused.stderr
    assert refused.stderr.count("\n") == 1
    both = cli.run(*args, "--out", str(tmp_path / "x"), "--no-execute", "--uav-noise", "1")
    assert both.returncode == 2 and "uav_noise > 0 needs execute" in both.stderr
    assert not (tmp_path / "x").exists()
