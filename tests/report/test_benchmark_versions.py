"""Runs of different benchmark versions never share a table unless asked (--mixed-versions);
a manifest written before versions were recorded is version 1."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from vlm_bench.report import load
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION, BenchmarkVersionError
from vlm_bench.types.records import EpisodeRecord

if TYPE_CHECKING:
    from tests.conftest import Cli

RUN_V1 = Path(__file__).parents[1] / "storage" / "data" / "run_v1"
"""A run folder of the first release: its manifest records no version."""


def _new_run(
    tmp_path: Path, make_run: Callable[..., Path], make_record: Callable[..., EpisodeRecord]
) -> Path:
    return make_run(tmp_path / "new", [make_record("m", "tower_stacking", 0, "explicit", 80.0)])


def test_an_old_run_beside_a_new_one_is_refused_in_one_line(
    tmp_path: Path, make_run: Callable[..., Path], make_record: Callable[..., EpisodeRecord]
) -> None:
    new = _new_run(tmp_path, make_run, make_record)
    with pytest.raises(BenchmarkVersionError) as info:
        load(new, RUN_V1)
    message = str(info.value)
    assert "\n" not in message
    assert f"new (version {BENCHMARK_VERSION})" in message
    assert "run_v1 (version 1, from before versions were recorded)" in message
    assert "--mixed-versions" in message


def test_mixed_versions_load_when_asked_with_a_version_column(
    tmp_path: Path, make_run: Callable[..., Path], make_record: Callable[..., EpisodeRecord]
) -> None:
    new = _new_run(tmp_path, make_run, make_record)
    frame = load(new, RUN_V1, mixed_versions=True)
    versions = frame.groupby("run")["benchmark_version"].unique().map(list).to_dict()
    assert versions == {"new": [BENCHMARK_VERSION], "run_v1": [1]}


def test_runs_of_one_version_share_a_table(
    tmp_path: Path, make_run: Callable[..., Path], make_record: Callable[..., EpisodeRecord]
) -> None:
    record = make_record("m", "tower_stacking", 0, "explicit", 80.0)
    first = make_run(tmp_path / "a", [record])
    second = make_run(tmp_path / "b", [record.model_copy(update={"run_id": "b"})])
    assert len(load(first, second)) == 2
    old_copy = tmp_path / "old_copy"
    shutil.copytree(RUN_V1, old_copy)
    assert set(load(RUN_V1, old_copy).benchmark_version) == {1}
    # A manifest that names version 1 is the same version as one that names none.
    named = make_run(tmp_path / "named_v1", [record], benchmark_version=1)
    assert json.loads((named / "manifest.json").read_text())["config"]["benchmark_version"] == 1
    assert set(load(RUN_V1, named).benchmark_version) == {1}


def test_report_cli_refuses_and_accepts_mixed_versions(
    cli: Cli,
    tmp_path: Path,
    make_run: Callable[..., Path],
    make_record: Callable[..., EpisodeRecord],
) -> None:
    new = str(_new_run(tmp_path, make_run, make_record))
    done = cli.run("report", new, str(RUN_V1), "--no-stats")
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: runs of different benchmark versions")
    assert (
        f"new (version {BENCHMARK_VERSION})" in lines[0]
        and "run_v1 (version 1, from before versions were recorded)" in lines[0]
    )
    out = cli.invoke(
        "report",
        new,
        str(RUN_V1),
        "--no-stats",
        "--mixed-versions",
        "--by",
        "run,benchmark_version",
        "-f",
        "markdown",
    )
    assert "| run_v1 | 1 | explicit |" in out and f"| new | {BENCHMARK_VERSION} | explicit |" in out
