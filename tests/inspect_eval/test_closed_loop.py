"""``vlm_bench/aerial -T loop=closed``: the same scripted answers give inspect the Succ@k, the
rounds and the replan conversations that ``vlm-bench run --loop closed --model mock`` records."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from inspect_ai import eval as inspect_eval
from inspect_ai.model import get_model

import vlm_bench
from tests.inspect_eval.conftest import first_user_text, scripted_mockllm
from vlm_bench.inspect_eval.task import aerial

TASKS = ("standard_pick_place", "tower_stacking")
OPTIONS = {
    "task": ",".join(TASKS), "seeds": "0", "instruction": "explicit", "resolution": 64,
    "loop": "closed", "max_rounds": 2,
}  # fmt: skip


def _script(samples: list[tuple[str, str]]) -> dict[str, list[str]]:
    """Per episode (key, GT plan): round 0 skips the approach (out of reach), the replan
    sends the whole GT plan; the second episode answers the GT plan at once."""
    script = {}
    for n, (key, gt_text) in enumerate(samples):
        gt = json.loads(gt_text)
        if n == 0:
            first = [s for s in gt if s["tasktype"] == "ARM"]
            script[key] = [json.dumps(first), json.dumps(gt), json.dumps(gt)]
        else:
            script[key] = [json.dumps(gt)]
    return script


def test_closed_loop_equals_a_closed_loop_run_of_the_same_answers(tmp_path: Path) -> None:
    task = aerial(**OPTIONS)  # type: ignore[arg-type]
    samples = [(str(s.id), str(s.target)) for s in task.dataset]
    keys = {"\n".join(first_user_text(s.input)): str(s.id) for s in task.dataset}  # type: ignore[arg-type]
    script = _script(samples)
    model = get_model("mockllm/model", custom_outputs=scripted_mockllm(script, keys))
    [log] = inspect_eval(task, model=model, log_dir=str(tmp_path / "logs"), display="none")
    assert log.status == "success", log.error

    outputs = tmp_path / "outputs.jsonl"
    outputs.write_text(
        "".join(json.dumps({"id": k, "rounds": r}) + "\n" for k, r in script.items())
    )
    run = vlm_bench.run(
        model="mock", backend_args={"file": str(outputs)}, out=tmp_path / "run",
        tasks=TASKS, seeds=(0,), instructions=("explicit",), resolution=64,
        loop="closed", max_rounds=2,
    )  # fmt: skip
    records = {r.key: r for r in run.records}

    assert log.samples is not None
    for sample in log.samples:
        score = next(iter((sample.scores or {}).values()))
        loop = (score.metadata or {})["loop"]
        record = records[str(sample.id)]
        assert record.loop is not None
        assert tuple(loop["succ_at"]) == record.loop.succ_at, sample.id
        assert loop["rounds_used"] == record.loop.rounds_used
        assert tuple(loop["failure_codes"]) == record.loop.failure_codes
        assert loop["end"] == record.loop.end
        # Each replan's key covers its prompt and the conversation before it: equal keys are
        # equal replan requests (views, feedback, history) to the run's.
        assert loop["replan_keys"] == [r.prompt_hash for r in record.rounds or ()]
        succ = {f"Succ@{k}": 100.0 * ok for k, ok in enumerate(record.loop.succ_at)}
        assert {k: score.value[k] for k in succ} == succ  # type: ignore[index]
    first, second = (records[key] for key, _ in samples)
    assert first.loop is not None and first.loop.succ_at == (False, True, True)  # recovered
    assert second.loop is not None and second.loop.succ_at == (True, True, True)
    assert log.results is not None
    metrics = {s.name: s.metrics for s in log.results.scores}
    assert metrics["Succ@0"]["grouped_overall"].value == pytest.approx(50.0)
    assert metrics["Succ@1"]["grouped_overall"].value == pytest.approx(100.0)
    # The run's results.json holds the same Succ@k (both instructions pooled: explicit only).
    results = json.loads((tmp_path / "run" / "results.json").read_text())
    pooled = {s["k"]: s["estimate"]["value"] for s in results["succ_at_k"]}
    assert pooled == {0: 50.0, 1: 100.0, 2: 100.0}


@pytest.mark.slow
def test_closed_loop_through_an_openai_compatible_server(tmp_path: Path) -> None:
    from tests.inspect_eval.conftest import FakeOpenAI

    task = aerial(**{**OPTIONS, "task": TASKS[0]})  # type: ignore[arg-type]
    samples = [(str(s.id), str(s.target)) for s in task.dataset]
    keys = {"\n".join(first_user_text(s.input)): str(s.id) for s in task.dataset}  # type: ignore[arg-type]
    with FakeOpenAI(_script(samples), keys) as server:
        model = get_model("openai-api/fake/served-model", base_url=server.url, api_key="k")
        [log] = inspect_eval(task, model=model, log_dir=str(tmp_path), display="none")
        received = list(server.received)
    assert log.status == "success", log.error
    assert log.samples is not None
    loop = (next(iter((log.samples[0].scores or {}).values())).metadata or {})["loop"]
    assert loop["succ_at"] == [False, True, True] and loop["rounds_used"] == 2
    # The replan: system, round 0 (its views as notes), the answer, the new views + feedback.
    replan = received[1]["messages"]
    assert [m["role"] for m in replan] == ["system", "user", "assistant", "user"]
    last = replan[-1]["content"]
    assert sum(1 for p in last if p["type"] == "image_url") == 4
    assert any("out_of_reach" in p.get("text", "") for p in last if p["type"] == "text")
