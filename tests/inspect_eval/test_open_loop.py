"""``vlm_bench/aerial`` open loop through inspect itself: scripted answers (``mockllm/model``)
and a local OpenAI-compatible server give the scores ``vlm-bench score`` gives them."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from inspect_ai import Task
from inspect_ai import eval as inspect_eval
from inspect_ai.log import EvalLog
from inspect_ai.model import get_model

import vlm_bench
from tests.inspect_eval.conftest import (
    EPISODES,
    FakeOpenAI,
    first_user_text,
    png_bytes,
    scripted_mockllm,
)
from vlm_bench.errors import MissingExtraError, VlmBenchError
from vlm_bench.inspect_eval.task import aerial

METRICS = ("S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ")


def _keys(task: Task) -> dict[str, str]:
    return {"\n".join(first_user_text(s.input)): str(s.id) for s in task.dataset}  # type: ignore[arg-type]


def _answers(task: Task) -> dict[str, list[str]]:
    """Per episode: the GT plan, a wrong first direction, prose, or a truncated plan."""
    out = {}
    for n, sample in enumerate(task.dataset):
        gt = json.loads(str(sample.target))
        if n % 4 == 1:
            gt[0]["direction"] = "back" if gt[0]["direction"] != "back" else "left"
        text = json.dumps(gt)
        text = {2: "I cannot see the cube.", 3: text[: len(text) // 2]}.get(n % 4, text)
        out[str(sample.id)] = [text]
    return out


def _expected(key: str, text: str) -> dict[str, float]:
    task_id, seed, variant = key.split("/")
    scores = vlm_bench.score_output(task_id, int(seed), text, variant).scores  # type: ignore[arg-type]
    return {
        "S_plan": scores.s_plan, "S_loc": scores.s_loc, "S_obj": scores.s_obj,
        "S_skill": scores.s_skill, "S_total": scores.s_total, "Succ": 100.0 * scores.succ,
    }  # fmt: skip


def _check(log: EvalLog, script: dict[str, list[str]]) -> None:
    assert log.status == "success", log.error
    assert log.samples is not None and len(log.samples) == 4
    by_suite: dict[str, list[dict[str, float]]] = {}
    for sample in log.samples:
        score = next(iter((sample.scores or {}).values()))
        expected = _expected(str(sample.id), script[str(sample.id)][0])
        assert score.value == pytest.approx(expected), sample.id
        by_suite.setdefault(sample.metadata["suite"], []).append(expected)
    assert log.results is not None
    metrics = {s.name: s.metrics for s in log.results.scores}
    suite_means = []
    for suite, rows in by_suite.items():
        mean = {m: sum(r[m] for r in rows) / len(rows) for m in METRICS}
        suite_means.append(mean)
        for m in METRICS:
            assert metrics[m][f"grouped_{suite}"].value == pytest.approx(mean[m])
    for m in METRICS:  # overall = the unweighted mean of the suites, as the paper's
        overall = sum(s[m] for s in suite_means) / len(suite_means)
        assert metrics[m]["grouped_overall"].value == pytest.approx(overall)


def test_registered_task_with_scripted_mockllm_scores_as_vlm_bench_score(tmp_path: Path) -> None:
    task = aerial(**EPISODES)  # type: ignore[arg-type]
    script = _answers(task)
    assert len({t[0] for t in script.values()}) == 4  # four different answers
    model = get_model("mockllm/model", custom_outputs=scripted_mockllm(script, _keys(task)))
    [log] = inspect_eval(
        "vlm_bench/aerial", model=model, task_args=EPISODES, log_dir=str(tmp_path),
        display="none",
    )  # fmt: skip
    assert log.eval.task == "vlm_bench/aerial"
    _check(log, script)


def test_samples_are_the_request_a_run_sends() -> None:
    task = aerial(**EPISODES)  # type: ignore[arg-type]
    sample = next(iter(task.dataset))
    task_id, seed, variant = str(sample.id).split("/")
    preview = vlm_bench.preview_prompt(
        task_id,
        int(seed),
        variant,
        resolution=64,
        snapshot_cache=False,  # type: ignore[arg-type]
    )
    system, user = sample.input  # type: ignore[misc]
    assert system.role == "system" and system.text == preview.request.system
    parts = [(c.type, c.text if c.type == "text" else png_bytes(c.image)) for c in user.content]
    images = [p[1] for p in parts if p[0] == "image"]
    assert images == [image.png for image in preview.request.images()]
    text = preview.text()
    for kind, value in parts:
        if kind == "text":
            assert value in text
    assert sample.metadata is not None and sample.metadata["benchmark_version"] >= 2


def test_openai_compatible_server_open_loop(tmp_path: Path, monkeypatch: Any) -> None:
    task = aerial(**EPISODES)  # type: ignore[arg-type]
    script = _answers(task)
    with FakeOpenAI(script, _keys(task)) as server:
        model = get_model("openai-api/fake/served-model", base_url=server.url, api_key="k")
        [log] = inspect_eval(task, model=model, log_dir=str(tmp_path), display="none")
        received = list(server.received)
    _check(log, script)
    assert len(received) == 4 and all(r["temperature"] == 0 for r in received)
    first = received[0]["messages"]
    assert [m["role"] for m in first] == ["system", "user"]
    urls = [p["image_url"]["url"] for p in first[1]["content"] if p["type"] == "image_url"]
    assert len(urls) == 4 and all(u.startswith("data:image/png;base64,") for u in urls)


def test_inspect_cli_finds_the_task_by_its_entry_point(tmp_path: Path) -> None:
    task = aerial(**EPISODES)  # type: ignore[arg-type]
    script = _answers(task)
    with FakeOpenAI(script, _keys(task)) as server:
        env = {**os.environ, "FAKE_API_KEY": "k", "FAKE_BASE_URL": server.url}
        args = ["-T", "task=standard_pick_place,tower_stacking", "-T", "seeds=0"]
        done = subprocess.run(
            [sys.executable, "-m", "inspect_ai", "eval", "vlm_bench/aerial", *args,
             "-T", "resolution=64", "--model", "openai-api/fake/served-model",
             "--log-dir", str(tmp_path), "--display", "none"],
            capture_output=True, text=True, env=env, timeout=300, check=False,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    [path] = tmp_path.glob("*.eval")
    from inspect_ai.log import read_eval_log

    log = read_eval_log(str(path))
    assert log.eval.task == "vlm_bench/aerial"
    _check(log, script)


def test_dataset_folder_gives_the_same_samples(tmp_path: Path) -> None:
    from vlm_bench.export.dataset_export import export_dataset
    from vlm_bench.export.options import export_options

    options = export_options(tasks=("standard_pick_place", "tower_stacking"), seeds=(0,),
                             resolution=64)  # fmt: skip
    export_dataset(tmp_path / "ds", options, progress=False)
    built = aerial(**EPISODES)  # type: ignore[arg-type]
    read = aerial(dataset=str(tmp_path / "ds"), task="tower_stacking", seeds="0")
    assert [s.id for s in read.dataset] == [s.id for s in built.dataset if "tower" in str(s.id)]
    for a, b in zip(read.dataset, [s for s in built.dataset if "tower" in str(s.id)], strict=True):
        assert a.input[0].text == b.input[0].text  # type: ignore[index]
        parts_a, parts_b = a.input[1].content, b.input[1].content  # type: ignore[index]
        assert [(p.type, getattr(p, "text", None)) for p in parts_a] == [
            (p.type, getattr(p, "text", None)) for p in parts_b
        ]
        assert [png_bytes(p.image) for p in parts_a if p.type == "image"] == [
            png_bytes(p.image) for p in parts_b if p.type == "image"
        ]


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"loop": "open", "perturb": "slip=0.3"}, "need -T loop=closed"),
        ({"loop": "sideways"}, "loop must be open or closed"),
        ({"seeds": "3-1"}, "empty seed range"),
        ({"suite": "nope"}, "unknown suite"),
        ({"dataset": "/nonexistent", "views": "uav"}, "the dataset's rows fix"),
    ],
)
def test_bad_task_options_are_one_line_errors(options: dict[str, Any], message: str) -> None:
    with pytest.raises(VlmBenchError, match=message):
        aerial(**options)


def test_a_missing_inspect_extra_names_it(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    from vlm_bench.inspect_eval.extra import require_inspect

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "inspect_ai" else real(name)
    )
    with pytest.raises(MissingExtraError, match=r"pip install 'vlm-bench\[inspect\]'"):
        require_inspect()


def test_inspect_cli_lists_and_numbers_read_as_the_cli_text() -> None:
    from vlm_bench.inspect_eval.options import task_options

    # inspect's -T turns "0,3" into ["0", "3"] (or [0, 3]) and "0" into 0.
    options = task_options(
        task=["standard_pick_place", "tower_stacking"], seeds=[0, 3], views=["uav", "side"],
        loop="closed", perturb=["slip=0.3", "bump=0.3"],
    )  # fmt: skip
    assert options.episodes.tasks == ("standard_pick_place", "tower_stacking")
    assert options.episodes.seeds == (0, 3) and options.episodes.views == ("uav", "side")
    assert options.perturb is not None and options.perturb.bump == 0.3
    assert task_options(seeds=0).episodes.seeds == (0,)
