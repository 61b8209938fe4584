"""Shared test setup: headless rendering, golden-update flag, and the CLI (in this process
through Typer's runner, or as the real console entry point in a subprocess: exit codes,
one-line errors on stderr)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from click.testing import Result
from typer.testing import CliRunner

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HF_HUB_OFFLINE", "1")

UPDATE_GOLDEN = os.environ.get("VLM_BENCH_UPDATE_GOLDEN") == "1"
ROOT = Path(__file__).resolve().parents[1]
SLOW_TESTS = Path(__file__).with_name("slow_tests.txt")


def _measured_slow() -> set[str]:
    """Node ids listed in ``slow_tests.txt`` (benchmarks/test_durations.py writes it)."""
    if not SLOW_TESTS.is_file():
        return set()
    lines = (line.split("#", 1)[0].strip() for line in SLOW_TESTS.read_text().splitlines())
    return {line for line in lines if line}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark ``slow`` every test measured over the bound, unless it is marked ``smoke``; runs
    before ``-m`` deselects, so the default ``-m 'not slow'`` leaves them out."""
    slow = _measured_slow()
    for item in items:
        if item.nodeid in slow and item.get_closest_marker("smoke") is None:
            item.add_marker(pytest.mark.slow)


def module_from_file(name: str, path: Path) -> ModuleType:
    """The Python file at ``path`` executed as a module called ``name`` (not put in
    ``sys.modules``): a benchmark script, a package's data-folder hook file, another test file."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_benchmark(name: str, *args: str, timeout: float = 300) -> str:
    """Run ``benchmarks/<name>`` with ``args`` in a fresh interpreter; it must exit 0. Returns
    its standard output."""
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    done = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / name), *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


class Cli:
    """``vlm-bench`` with every command registered."""

    def __init__(self) -> None:
        from vlm_bench.cli.main import _register, app

        _register()
        self.app = app

    def invoke(self, *args: str) -> str:
        """Run a command in this process; it must exit 0. Returns its output."""
        result = CliRunner().invoke(self.app, list(args), catch_exceptions=False)
        assert result.exit_code == 0, result.output
        return result.output

    def result(self, *args: str) -> Result:
        """Run a command in this process; its exception, if any, is kept in the result."""
        return CliRunner().invoke(self.app, list(args))

    @staticmethod
    def command(*args: str) -> list[str]:
        """The argv of the real console entry point with ``args`` (for ``subprocess``)."""
        return [sys.executable, "-c", "from vlm_bench.cli.main import main; main()", *args]

    @staticmethod
    def run_args(
        out: Path, model: str, tasks: Sequence[str], seeds: str, *options: str
    ) -> list[str]:
        """``run`` arguments: ``model`` on ``tasks`` x ``seeds`` into ``out`` with no progress
        bar, plus ``options``."""
        args = ["run", "--model", model, "--seeds", seeds, *options, "--out", str(out)]
        args.append("--no-progress")
        for task in tasks:
            args += ["--task", task]
        return args

    @staticmethod
    def wait_for_records(
        proc: subprocess.Popen[Any], records: Path, n: int, timeout: float = 60
    ) -> int:
        """Wait until ``records`` (a run's records.jsonl) has ``n`` lines while ``proc`` runs;
        fails if the run ended first. Returns the lines written."""
        deadline = time.monotonic() + timeout
        while proc.poll() is None and time.monotonic() < deadline:
            if _lines(records) >= n:
                break
            time.sleep(0.005)
        assert proc.poll() is None, "the run ended before it could be stopped"
        return _lines(records)

    def run(
        self,
        *args: str,
        cwd: Path = ROOT,
        env: dict[str, str] | None = None,
        timeout: float = 120,
    ) -> subprocess.CompletedProcess[str]:
        """Run the real console entry point in a subprocess."""
        return subprocess.run(
            self.command(*args),
            capture_output=True,
            text=True,
            cwd=cwd,
            env=env,
            timeout=timeout,
            check=False,
        )


@pytest.fixture
def cli() -> Cli:
    """The CLI, to invoke in process or run as a subprocess."""
    return Cli()


def _lines(path: Path) -> int:
    try:
        return path.read_bytes().count(b"\n")
    except FileNotFoundError:
        return 0
