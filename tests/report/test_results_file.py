"""results.json: written by every run, valid against its committed schema, read by report."""

from __future__ import annotations

import io
import json
import shutil
from pathlib import Path
from typing import TYPE_CHECKING

import jsonschema
import pandas as pd
import pytest

import vlm_bench
from vlm_bench.errors import DataFileError
from vlm_bench.report.results_file import build_results, read_results, write_results
from vlm_bench.types.results import RESULTS_SCHEMA_VERSION, results_json_schema

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "docs" / "results.schema.json"
SUITES = ("standard_pick_place", "target_color_yellow", "synonym_block_bin", "tower_stacking")


def test_the_committed_schema_is_the_models() -> None:
    committed = json.loads(SCHEMA.read_text())
    assert committed == json.loads(json.dumps(results_json_schema())), (
        "docs/results.schema.json is stale: regenerate it with python -c 'import json; from "
        "vlm_bench.types.results import results_json_schema as s; "
        "print(json.dumps(s(), indent=1, sort_keys=True))' > docs/results.schema.json"
    )


@pytest.mark.parametrize("run", ["oracle", "random", "mock"])
def test_every_run_writes_a_results_file_valid_against_the_schema(
    real_runs: dict[str, Path], run: str
) -> None:
    data = json.loads((real_runs[run] / "results.json").read_text())
    jsonschema.validate(data, json.loads(SCHEMA.read_text()))
    assert data["schema_version"] == RESULTS_SCHEMA_VERSION
    assert data["benchmark"] == "vlm-bench" and data["benchmark_version"] >= 2
    assert data["model"]["name"] == run and data["config_hash"]
    assert data["protocol"]["name"] == "custom"  # 64 px views


def test_results_hold_the_summary_tables_values(real_runs: dict[str, Path]) -> None:
    run = vlm_bench.load_run(real_runs["mock"])
    results = read_results(real_runs["mock"] / "results.json")
    # The mock run: 8 episodes, a quarter answered with a backend error.
    assert results.counts.episodes == 8 and results.counts.errors == 2
    assert results.counts.answered == 6 and results.counts.executed == 0
    summary = run.summary.set_index(["instruction", "suite"])
    for row in results.results:
        for group in row.groups:
            expected = summary.loc[(row.instruction, group.group)]
            assert group.n == expected["n"]
            for metric in ("S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ"):
                assert group.metrics[metric].value == pytest.approx(expected[metric])
    overall = results.overall("both")
    assert overall is not None and "exec_success" not in overall.metrics


def test_intervals_bracket_the_values_and_executed_runs_add_exec_and_task(
    make_run, make_record, make_execution, tmp_path: Path
) -> None:
    tasks = ("standard_pick_place", "color_distractor_green")  # two tasks: intervals vary
    records = [
        make_record("m", t, s, v, 40.0 + 20 * s + 10 * n, succ=s == 1,
                    executed=make_execution(s == 1, 50.0 + 50 * s))
        for n, t in enumerate(tasks) for s in (0, 1) for v in ("explicit", "implicit")
    ]  # fmt: skip
    run = make_run(tmp_path / "run", records, seeds=(0, 1))
    results = build_results(run, n_boot=200)
    base = results.results[0].groups[0]
    assert base.group == "base_manipulation" and base.n == 4
    total = base.metrics["S_total"]
    assert total.value == pytest.approx(55.0)
    assert total.lo is not None and total.hi is not None and total.lo <= 55.0 <= total.hi
    assert base.metrics["exec_success"].value == pytest.approx(50.0)
    assert base.metrics["S_task"].value == pytest.approx(75.0)
    assert results.counts.executed == 8 and results.succ_at_k == []


def test_report_reads_results_files_as_well_as_run_folders(
    cli: Cli, real_runs: dict[str, Path], tmp_path: Path
) -> None:
    oracle = real_runs["oracle"]
    # A run folder's results.json stands for the folder.
    beside = cli.invoke("report", str(oracle / "results.json"), "-f", "markdown", "--no-stats")
    assert "| oracle | explicit | 100.0 |" in beside
    # Files on their own (a leaderboard's): their table, each row with its protocol.
    files = []
    for run in ("oracle", "random"):
        files.append(tmp_path / f"{run}.json")
        shutil.copy(real_runs[run] / "results.json", files[-1])
    text = cli.invoke("report", *map(str, files), "-f", "markdown")
    assert "| oracle | custom | explicit | 100.0 |" in text
    assert "| random | custom | both |" in text
    csv = pd.read_csv(io.StringIO(cli.invoke("report", *map(str, files), "-f", "csv")))
    oracle_overall = csv[(csv.run == "oracle") & (csv.suite == "overall")]
    assert (oracle_overall["S_total"] == 100.0).all()
    mixed = cli.result("report", str(files[0]), str(oracle))
    assert isinstance(mixed.exception, Exception) and "not both" in str(mixed.exception)


def test_a_broken_results_file_names_the_file_and_field(tmp_path: Path) -> None:
    bad = tmp_path / "results.json"
    bad.write_text(json.dumps({"schema_version": 1, "benchmark": "vlm-bench"}))
    match = r"results\.json.*not a results\.json: benchmark_version"
    with pytest.raises(DataFileError, match=match):
        read_results(bad)


def test_rescore_writes_results_again(real_runs: dict[str, Path], tmp_path: Path) -> None:
    copy = tmp_path / "oracle"
    shutil.copytree(real_runs["oracle"], copy)
    (copy / "results.json").unlink()
    vlm_bench.rescore(copy)
    assert read_results(copy / "results.json").counts.episodes == 8
    (copy / "results.json").unlink()
    assert write_results(copy) == copy / "results.json" and (copy / "results.json").exists()
