"""Refusals that carry their cause: a garbled plan file, a camera without a video, a plan over
the step cap, a report file that cannot be written, a run folder of another benchmark version."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vlm_bench.cli.main import main
from vlm_bench.parsing.schema import MAX_PLAN_STEPS
from vlm_bench.storage import RunPaths, read_manifest

TASK = "standard_pick_place"


def _main(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    with pytest.raises(SystemExit) as exit_info:
        main(list(args))
    code = exit_info.value.code
    return (code if isinstance(code, int) else 1), capsys.readouterr().err


def _one_line(code: int, err: str, *needles: str) -> str:
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    for needle in needles:
        assert needle in lines[0], lines[0]
    return lines[0]


def test_a_plan_file_that_is_not_utf8_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    plan = tmp_path / "plan.json"
    step = b'[{"subtask": 0, "tasktype": "ARM", "object": "gray_cube\xff", "skill": "pick"}]'
    plan.write_bytes(step)
    code, err = _main(capsys, "execute", TASK, "--plan", str(plan))
    _one_line(code, err, str(plan), "not UTF-8", "0xff")


def test_a_camera_without_a_video_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    code, err = _main(capsys, "execute", TASK, "--camera", "bogus")
    _one_line(code, err, "--camera bogus", "--video")


def test_a_plan_over_the_cap_is_refused_naming_the_cap(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    plan = tmp_path / "long.json"
    steps = [{"subtask": i, "tasktype": "UAV", "direction": "front"} for i in range(10_000)]
    plan.write_text(json.dumps(steps))
    code, err = _main(capsys, "execute", TASK, "--plan", str(plan))
    _one_line(code, err, f"more than {MAX_PLAN_STEPS} steps", "long.json")


@pytest.fixture(scope="module")
def small_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    import vlm_bench

    out = tmp_path_factory.mktemp("runs") / "oracle"
    vlm_bench.run(model="oracle", tasks=(TASK,), seeds=(0,), resolution=32, execute=False, out=out)
    return out


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs /proc")
def test_a_report_file_that_cannot_be_written_names_the_path_given(
    capsys: pytest.CaptureFixture[str], small_run: Path
) -> None:
    code, err = _main(capsys, "report", str(small_run), "-f", "latex", "--out", "/proc/x.tex")
    assert code != 0 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].endswith(": /proc/x.tex"), err
    assert ".tmp" not in err


def test_resuming_a_run_of_another_benchmark_version_says_what_to_do(
    capsys: pytest.CaptureFixture[str], small_run: Path, tmp_path: Path
) -> None:
    import shutil

    old = tmp_path / "old"
    shutil.copytree(small_run, old)
    paths = RunPaths(old)
    data = json.loads(paths.manifest.read_text())
    data["config"]["benchmark_version"] = 1
    paths.manifest.write_text(json.dumps(data))
    assert read_manifest(paths).config.benchmark_version == 1
    args = ("run", "--model", "oracle", "--task", TASK, "--seeds", "0", "--resolution", "32")
    code, err = _main(capsys, *args, "--no-execute", "--no-progress", "--out", str(old))
    line = _one_line(code, err, "benchmark version 1", "--out/--run-name")
    assert "same options" not in line
