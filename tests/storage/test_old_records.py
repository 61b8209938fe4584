"""Result files written by earlier releases keep loading (schema_version + tolerant loading).

``data/run_v1/`` is a run folder written by the first release (record schema 1) with the mock
backend: an exact plan, a fenced plan with a wrong direction, a refusal, and a backend error.
Never regenerate it: it stands for users' existing results.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from vlm_bench.errors import DataFileError
from vlm_bench.report import load_records_frame, summary_long
from vlm_bench.storage import RunPaths, latest_records, read_manifest, read_records, read_responses
from vlm_bench.types.records import EpisodeRecord

RUN_V1 = Path(__file__).parent / "data" / "run_v1"


def test_v1_run_folder_loads() -> None:
    manifest = read_manifest(RunPaths(RUN_V1))
    assert manifest.schema_version == 1 and manifest.config.model == "mock"
    records = {r.key: r for r in latest_records(RUN_V1 / "records.jsonl")}
    assert len(records) == 4
    exact = records["standard_pick_place/0/explicit"]
    assert exact.ok and exact.scores is not None and exact.scores.succ
    assert exact.parse is not None and exact.parse.tier == "valid"
    fenced = records["standard_pick_place/0/implicit"]
    assert fenced.parse is not None and fenced.parse.tier == "repaired"
    assert fenced.scores is not None and fenced.scores.s_loc == 40.0
    assert "wrong_direction" in fenced.error_tags
    refusal = records["tower_stacking/0/explicit"]
    assert refusal.scores is not None and refusal.scores.s_total == 0.0
    failed = records["tower_stacking/0/implicit"]
    assert failed.status == "error" and failed.backend_error == "HTTP 503: server overloaded"
    assert len(read_responses(RUN_V1 / "responses.jsonl")) == 3
    # Written before plan execution existed: read as a run that does not execute plans.
    assert manifest.config.execute is False and manifest.config.uav_noise == 0.0
    assert all(r.execution is None for r in records.values())


def test_v1_records_feed_the_summary() -> None:
    long = summary_long(load_records_frame(RUN_V1))
    row = long[(long.instruction == "explicit") & (long.suite == "overall")].iloc[0]
    assert row.S_total == pytest.approx(50.0) and row.Succ == pytest.approx(50.0)
    assert "exec_success" not in long.columns


def test_unknown_fields_are_ignored_and_new_fields_default(tmp_path: Path) -> None:
    line = json.loads((RUN_V1 / "records.jsonl").read_text().splitlines()[0])
    line["field_from_the_future"] = {"x": 1}
    for optional in ("finish_reason", "cached", "gt_plan", "plan", "created", "schema_version"):
        line.pop(optional)
    path = tmp_path / "records.jsonl"
    path.write_text(json.dumps(line) + "\n")
    (record,) = read_records(path)
    assert isinstance(record, EpisodeRecord)
    assert record.schema_version == 1 and record.cached is False and record.gt_plan == []


def test_invalid_record_names_file_line_and_field(tmp_path: Path) -> None:
    shutil.copy(RUN_V1 / "records.jsonl", tmp_path / "records.jsonl")
    lines = (tmp_path / "records.jsonl").read_text().splitlines()
    broken = json.loads(lines[1])
    broken["seed"] = "not a seed"
    lines[1] = json.dumps(broken)
    (tmp_path / "records.jsonl").write_text("\n".join(lines) + "\n")
    with pytest.raises(DataFileError, match=r"records\.jsonl: line 2: seed"):
        read_records(tmp_path / "records.jsonl")
