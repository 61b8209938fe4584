"""``vlm-bench export demos`` refuses bad input in one line (exit 2), before writing anything:
test seeds, a non-empty folder, an odd image size, an unknown view, a missing extra."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from vlm_bench.cli.main import main

TASK = ("--task", "standard_pick_place")


def _main(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    with pytest.raises(SystemExit) as exit_info:
        main(list(args))
    code = exit_info.value.code
    return (code if isinstance(code, int) else 1), capsys.readouterr().err


def _refused(capsys: pytest.CaptureFixture[str], out: Path, *args: str) -> str:
    code, err = _main(capsys, "export", "demos", str(out), "--no-progress", *TASK, *args)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), err
    return lines[0]


def test_test_seeds_are_refused_unless_allowed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    line = _refused(capsys, tmp_path / "out", "--seeds", "8-12")
    assert "test seeds asked for (8, 9)" in line and "--allow-test-seeds" in line
    assert not (tmp_path / "out").exists()


def test_a_non_empty_folder_is_refused_without_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    line = _refused(capsys, out, "--seeds", "10")
    assert "not empty" in line and "--force" in line
    assert [p.name for p in out.iterdir()] == ["keep.txt"]


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--size", "65"), "--size must be even"),
        (("--size", "8"), "size"),
        (("--views", "wrist,periscope"), "unknown camera view 'periscope'"),
        (("--instruction", "both"), "unknown instruction variant 'both'"),
        (("--task", "no_such_task"), "unknown task 'no_such_task'"),
    ],
)
def test_bad_options_are_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: tuple[str, ...], needle: str
) -> None:
    assert needle in _refused(capsys, tmp_path / "out", "--seeds", "10", *args)
    assert not (tmp_path / "out").exists()


def test_a_missing_extra_names_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    real = importlib.util.find_spec

    def without_pyarrow(name: str, *rest: object) -> object:
        return None if name == "pyarrow" else real(name, *rest)  # type: ignore[arg-type]

    monkeypatch.setattr(importlib.util, "find_spec", without_pyarrow)
    line = _refused(capsys, tmp_path / "out", "--seeds", "10")
    assert "pyarrow" in line and "vlm-bench[demos]" in line
    assert not (tmp_path / "out").exists()
