"""``vlm_bench.score_answer``: a dataset row's (or an episode key's) answer scored exactly as
``vlm-bench score`` scores it, without the simulator; rows of another version refused."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import datasets
import pytest

import vlm_bench
from vlm_bench.errors import VlmBenchError
from vlm_bench.export.dataset_export import DatasetExport
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION, BenchmarkVersionError

if TYPE_CHECKING:
    from tests.conftest import Cli


def _answers(row: dict[str, Any]) -> list[str]:
    """The GT plan, the GT plan with its last step dropped and a UAV move turned, a plan
    naming an unknown object, prose, and nothing."""
    gt = json.loads(row["gt_plan"])
    changed = [dict(s) for s in gt[:-1]]
    for step in changed:
        if step["tasktype"] == "UAV":
            step["direction"] = "back" if step["direction"] != "back" else "front"
            break
    unknown = [dict(gt[-1], object="unicorn")] if gt[-1]["tasktype"] == "ARM" else gt
    return [
        json.dumps(gt),
        "Here is my plan:\n```json\n" + json.dumps(changed) + "\n```",
        json.dumps(unknown),
        "I cannot see the table.",
        "",
    ]


def test_rows_and_keys_score_as_the_score_command(
    small: DatasetExport, cli: Cli, tmp_path: Path
) -> None:
    rows = datasets.load_dataset(str(small.folder), split="test")
    seen = set()
    for row in rows:
        task, seed, variant = row["key"].split("/")
        for i, answer in enumerate(_answers(row)):
            path = tmp_path / f"{i}.txt"
            path.write_text(answer)
            expected = json.loads(
                cli.invoke(
                    "score",
                    task,
                    "--seed",
                    seed,
                    "--instruction",
                    variant,
                    "--output",
                    str(path),
                    "--json",
                )
            )
            by_row = vlm_bench.score_answer(row, answer)
            by_key = vlm_bench.score_answer(row["key"], answer)
            assert by_row.model_dump(mode="json") == expected
            assert by_key.model_dump(mode="json") == expected
            seen.add((round(by_row.scores.s_total, 3), by_row.scores.succ))
    assert (100.0, True) in seen and len(seen) >= 4  # the answers span different scores


def test_scoring_needs_no_simulator(small: DatasetExport) -> None:
    row = datasets.load_dataset(str(small.folder), split="test")[2]
    code = """
import json, sys
sys.modules["mujoco"] = None  # importing it now raises ImportError
sys.modules["mink"] = None
import vlm_bench
from vlm_bench.errors import VlmBenchError
row = json.loads(sys.stdin.read())
scores = vlm_bench.score_answer(row, row["gt_plan"]).scores
scores_key = vlm_bench.score_answer(row["key"], "[]").scores
print(scores.s_total, scores.succ, scores_key.s_total)
print(sorted(m for m in sys.modules if m.startswith(("vlm_bench.sim", "vlm_bench.episodes"))))
"""
    data = {k: row[k] for k in ("key", "benchmark_version", "objects", "gt_plan", "suite")}
    done = subprocess.run(
        [sys.executable, "-c", code],
        input=json.dumps(data),
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["100.0 True 0.0", "[]"]


def test_a_row_of_another_version_is_refused(small: DatasetExport) -> None:
    row = dict(datasets.load_dataset(str(small.folder), split="test")[0])
    row["benchmark_version"] = BENCHMARK_VERSION + 1
    with pytest.raises(BenchmarkVersionError) as caught:
        vlm_bench.score_answer(row, row["gt_plan"])
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(
        f"dataset row {row['key']} is benchmark version {BENCHMARK_VERSION + 1}; this release "
        f"scores version {BENCHMARK_VERSION}"
    )


@pytest.mark.parametrize(
    ("target", "message"),
    [
        ("drawer_interaction/0", "episode key must be task_id/seed/variant"),
        ("drawer_interaction/x/explicit", "episode key must be task_id/seed/variant"),
        ("no_such_task/0/explicit", "unknown task 'no_such_task'"),
        ("drawer_interaction/9999/explicit", "is not in the committed ground truth"),
        ({"key": "drawer_interaction/0/explicit"}, "not a vlm-bench dataset row: it lacks"),
    ],
)
def test_bad_targets_are_one_line_errors(target: Any, message: str) -> None:
    with pytest.raises(VlmBenchError, match=message):
        vlm_bench.score_answer(target, "[]")
