"""lmms-eval's own command line runs ``vlm_bench_aerial`` and ``vlm_bench_aerial_text`` with its
OpenAI-compatible model against a local server that answers from a fixed table: it sends each
episode's prompt as a run does, and its metrics are the means of ``vlm-bench score`` of the same
answers, overall and per suite.

lmms-eval is installed without its dependencies beside this environment
(benchmarks/lmms_eval_env.py; ``VLM_BENCH_LMMS_EVAL_ENV`` names a folder to reuse)."""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import datasets
import pytest
from PIL import Image

from vlm_bench.export.dataset_export import DatasetExport
from vlm_bench.export.row_model import user_parts
from vlm_bench.lmms import TASKS_DIR

from .conftest import SMALL
from .fake_openai import fake_openai

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
METRICS = ("s_plan", "s_loc", "s_obj", "s_skill", "s_total", "succ")


def _lmms_eval_env(tmp_path_factory: pytest.TempPathFactory) -> Path:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        from lmms_eval_env import install
    finally:
        sys.path.pop(0)
    given = os.environ.get("VLM_BENCH_LMMS_EVAL_ENV")
    return install(Path(given) if given else tmp_path_factory.mktemp("lmms-eval"))


def _text_of(messages: list[dict[str, Any]]) -> str:
    """The user turn's text parts, joined: which episode a request is."""
    (user,) = [m for m in messages if m["role"] == "user"]
    return "\n".join(c["text"] for c in user["content"] if c["type"] == "text")


def _answers(gt: list[dict[str, Any]], i: int) -> str:
    """A different kind of answer for each episode: the GT plan, the plan less its last step,
    a plan in prose and fences with a UAV move turned, and no plan."""
    kind = i % 4
    if kind == 0:
        return json.dumps(gt)
    if kind == 1:
        return json.dumps(gt[:-1])
    if kind == 2:
        turned = [dict(s) for s in gt]
        for step in turned:
            if step["tasktype"] == "UAV":
                step["direction"] = "back" if step["direction"] != "back" else "front"
                break
        return "Plan:\n```json\n" + json.dumps(turned) + "\n```"
    return "I need a closer look first."


@pytest.mark.slow
def test_lmms_eval_metrics_are_vlm_bench_scores(
    tmp_path: Path,
    tmp_path_factory: pytest.TempPathFactory,
    small: DatasetExport,
    exporter: Callable[..., DatasetExport],
    cli: Cli,
) -> None:
    target = _lmms_eval_env(tmp_path_factory)
    text = exporter("small-text", **SMALL, scene_as_text=True)
    shutil.copytree(small.folder, tmp_path / "vlm-bench-aerial")
    shutil.copytree(text.folder, tmp_path / "vlm-bench-aerial-text")
    rows = {
        name: list(datasets.load_dataset(str(tmp_path / folder), split="test"))
        for name, folder in [
            ("vlm_bench_aerial", "vlm-bench-aerial"),
            ("vlm_bench_aerial_text", "vlm-bench-aerial-text"),
        ]
    }
    table: dict[str, tuple[str, dict[str, Any]]] = {}  # user text -> (answer, row)
    for task_rows in rows.values():
        for i, row in enumerate(task_rows):
            key = "\n".join(v for kind, v in user_parts(row["user"]) if kind == "text")
            table[key] = (_answers(json.loads(row["gt_plan"]), i), row)
    assert len(table) == 8  # every episode's prompt differs

    with fake_openai(lambda messages: table[_text_of(messages)][0]) as (url, seen):
        command = [sys.executable, "-m", "lmms_eval", "eval", "--model", "openai"]
        command += ["--model_args", f"model=fake,base_url={url},api_key=none"]
        command += ["--tasks", "vlm_bench_aerial,vlm_bench_aerial_text"]
        command += ["--include_path", str(TASKS_DIR), "--batch_size", "1"]
        command += ["--output_path", str(tmp_path / "out"), "--log_samples"]
        env = {**os.environ, "PYTHONPATH": str(target), "HF_HUB_OFFLINE": "1"}
        done = subprocess.run(
            command,
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=900,
            check=False,
        )
    assert done.returncode == 0, done.stderr[-3000:]
    assert len(seen) == 8

    for messages in seen:  # the request a run sends: system, then text and images in order
        row = table[_text_of(messages)][1]
        system, user = messages
        assert system["role"] == "system" and system["content"][0]["text"] == row["system"]
        shown = []
        for part in user["content"]:
            if part["type"] == "text":
                shown.append(part["text"])
                continue
            png = base64.b64decode(part["image_url"]["url"].split(",", 1)[1])
            pixels = Image.open(io.BytesIO(png)).convert("RGB").tobytes()
            (view,) = [
                v for v in row["views"] if row[f"image_{v}"].convert("RGB").tobytes() == pixels
            ]
            shown.append(f"<image:{view}>")
        assert "\n".join(shown) == row["user"]

    (results_file,) = (tmp_path / "out").rglob("*_results.json")
    results = json.loads(results_file.read_text())["results"]
    for task, task_rows in rows.items():
        scores = []
        for i, row in enumerate(task_rows):
            answer_file = tmp_path / f"{task}-{i}.txt"
            answer_file.write_text(_answers(json.loads(row["gt_plan"]), i))
            task_id, seed, variant = row["key"].split("/")
            data = json.loads(
                cli.invoke(
                    "score",
                    task_id,
                    "--seed",
                    seed,
                    "--instruction",
                    variant,
                    "--output",
                    str(answer_file),
                    "--json",
                )
            )
            values = {m: float(data["scores"][m]) for m in METRICS}
            values["succ"] = 100.0 if data["scores"]["succ"] else 0.0
            scores.append((row["suite"], values))
        suites = sorted({suite for suite, _ in scores})
        assert len(suites) == 2
        for metric in METRICS:
            overall = [v[metric] for _, v in scores]
            assert results[task][f"{metric},none"] == pytest.approx(sum(overall) / len(overall))
            for suite in suites:
                part = [v[metric] for s, v in scores if s == suite]
                got = results[task][f"{metric}_{suite},none"]
                assert got == pytest.approx(sum(part) / len(part)), (task, metric, suite)
        assert {v["succ"] for _, v in scores} == {0.0, 100.0}  # the answers differ in kind
