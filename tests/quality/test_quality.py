"""Static quality gates run by the test suite: ruff (lint and format), mypy --strict,
import-linter layers."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(args, cwd=ROOT, capture_output=True, text=True, check=False)


def _tool(name: str) -> str:
    path = shutil.which(name) or str(Path(sys.executable).parent / name)
    if not Path(path).exists():
        pytest.skip(f"{name} not installed (pip install 'vlm-bench[dev]')")
    return path


def test_ruff_clean() -> None:
    result = _run(_tool("ruff"), "check", "vlm_bench", "tests", "benchmarks")
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_formatted() -> None:
    """``ruff format`` leaves the code as it is (the style is the formatter's, not a debate)."""
    result = _run(_tool("ruff"), "format", "--check", "vlm_bench", "tests", "benchmarks")
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_strict() -> None:
    result = _run(sys.executable, "-m", "mypy", "--strict", "vlm_bench")
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr


def test_import_layers() -> None:
    result = _run(_tool("lint-imports"))
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr


def test_help_does_not_import_heavy_modules() -> None:
    code = (
        "import sys\n"
        "from typer.testing import CliRunner\n"
        "from vlm_bench.cli.main import app, _register\n"
        "_register()\n"
        "r = CliRunner().invoke(app, ['--help'])\n"
        "assert r.exit_code == 0, r.output\n"
        "heavy = [m for m in ('torch', 'transformers', 'vllm', 'openai', 'mujoco', 'mink')"
        " if m in sys.modules]\n"
        "print(','.join(heavy))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=False
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "", f"--help imported: {result.stdout}"
