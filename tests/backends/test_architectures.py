"""Every architecture of the paper's VLMs (plus LLaVA), as a tiny random-weight model built from
config with a locally trained tokenizer (no hub): it loads as the card says, the four labelled
views reach it (image tokens counted, each view after its label), and greedy batch 8 equals
batch 1. ``vlm-bench run --model <folder>`` runs end to end where the processor can be saved
and loaded: LLaVA here; the five whose processors hold a torchvision video processor skip
without torchvision (``benchmarks/architectures_gpu.py`` runs them all on a GPU machine).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("transformers")


from vlm_bench.backends.hf import HfBackend  # noqa: E402
from vlm_bench.catalog.model_cards import model_cards  # noqa: E402
from vlm_bench.types.generation import (  # noqa: E402
    GenerationConfig,
)

ROOT = Path(__file__).resolve().parents[2]
NO_TORCHVISION = (
    "its processor holds a video processor that needs torchvision (even for images); "
    "torchvision has no CPU build here"
)


def _load_tiny() -> ModuleType:
    spec = importlib.util.spec_from_file_location("tiny_vlms", ROOT / "benchmarks/tiny_vlms.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["tiny_vlms"] = module
    spec.loader.exec_module(module)
    return module


tiny = _load_tiny()
ARCHS = {arch.name: arch for arch in tiny.ARCHS}


@pytest.fixture(scope="module")
def system_prompt() -> str:
    """The benchmark's own system prompt (no few-shot examples), to train the tokenizer on."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.prompting import build_prompt
    from vlm_bench.types.run import RunConfig

    episode = get_episode("standard_pick_place", 0)
    config = RunConfig(model="mock", images=False, k_shot=0).prompt_config("explicit")
    return build_prompt(episode, {}, config).to_request("x").system


@pytest.fixture(scope="module")
def corpus(system_prompt: str) -> list[str]:
    plan = '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}]'
    return [system_prompt, *tiny.VIEWS.values(), plan, "pick the gray cube"] * 3


@pytest.fixture(scope="module", params=sorted(ARCHS))
def built(request: pytest.FixtureRequest, corpus: list[str]) -> Iterator[tuple[Any, Any]]:
    arch = ARCHS[request.param]
    yield arch, arch.build(corpus)


def _check_views_reach_the_model(
    rows: list[list[int]], tokenizer: Any, image_id: int, per_view: int
) -> None:
    """Every prompt holds the four views, in order, each after its label and whole."""
    expected = [(view, per_view) for view in tiny.VIEWS]
    for seen in tiny.views_reaching_the_model(rows, tokenizer, image_id):
        assert seen == expected


def test_built_from_config_loads_as_its_card_says(built: tuple[Any, Any], tmp_path: Path) -> None:
    from transformers import AutoModelForImageTextToText

    arch, parts = built
    parts.model.save_pretrained(tmp_path)
    loaded = AutoModelForImageTextToText.from_pretrained(tmp_path)
    assert type(loaded).__name__ == arch.architecture
    if arch.card is not None:
        assert model_cards()[arch.card].architecture == arch.architecture


def test_four_labelled_views_reach_the_model_and_batches_agree(
    built: tuple[Any, Any], system_prompt: str
) -> None:
    """Through the hf backend's own encode and generate (the processor built around its PIL
    image processor, without the video processor, where torchvision is missing)."""
    arch, parts = built
    processor = parts.in_memory_processor()
    backend = HfBackend.from_loaded(arch.name, processor, parts.model)
    requests = tiny.four_view_requests(system_prompt, 8)
    with tiny.encoded_prompts() as rows:
        one = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=1))
        eight = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=8))
    assert all(r.error is None for r in one + eight)
    assert [r.text for r in eight] == [r.text for r in one]
    per_view = tiny.tokens_per_view(processor, parts.image_token_id, system_prompt)
    assert per_view > 0 and len(rows) == 16
    _check_views_reach_the_model(rows, backend.tokenizer, parts.image_token_id, per_view)


def test_vlm_bench_run_end_to_end(built: tuple[Any, Any], tmp_path: Path) -> None:
    arch, parts = built
    if arch.video_processor and not tiny.has_torchvision():
        pytest.skip(f"{arch.name}: {NO_TORCHVISION}")
    model = parts.save(tmp_path / arch.name)
    with tiny.encoded_prompts() as rows:
        tiny.cli_run(tmp_path / "batch1", model, 1, "--resolution", "112")
        tiny.cli_run(tmp_path / "batch8", model, 8, "--resolution", "112")
    one, eight = tiny.run_outputs(tmp_path / "batch1"), tiny.run_outputs(tmp_path / "batch8")
    assert len(one) == 8 and eight == one
    records = [json.loads(line) for line in (tmp_path / "batch8/records.jsonl").open()]
    batch = records[0]["batch_latency_s"]  # one batch of 8: each record holds an eighth of it
    assert batch > 0 and all(r["batch_latency_s"] == batch for r in records)
    assert sum(r["latency_s"] for r in records) == pytest.approx(batch)
    processor = parts.processor()
    per_view = tiny.tokens_per_view(processor, parts.image_token_id, "")
    assert len(rows) == 16
    _check_views_reach_the_model(rows, processor.tokenizer, parts.image_token_id, per_view)


def test_a_two_round_conversation_with_images_reaches_the_model(
    built: tuple[Any, Any], system_prompt: str
) -> None:
    """A closed loop's replan (``--history images``): the first user turn's four views, the
    model's answer, then the replan's four views: eight labelled views in order, and the
    answer's text between them."""
    from vlm_bench.types.generation import TextPart, Turn

    arch, parts = built
    processor = parts.in_memory_processor()
    backend = HfBackend.from_loaded(arch.name, processor, parts.model)
    first, now = tiny.four_view_requests(system_prompt, 2)
    answer = '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}]'
    history = (
        Turn(role="user", content=first.user),
        Turn(role="assistant", content=(TextPart(text=answer),)),
    )
    replan = now.model_copy(update={"history": history})
    with tiny.encoded_prompts() as rows:
        (result,) = backend.generate([replan], GenerationConfig(max_new_tokens=4))
    assert result.error is None
    (row,) = rows
    per_view = tiny.tokens_per_view(processor, parts.image_token_id, system_prompt)
    (seen,) = tiny.views_reaching_the_model(rows, backend.tokenizer, parts.image_token_id)
    assert [view for view, _ in seen] == list(tiny.VIEWS) * 2
    assert sum(n for _, n in seen) >= 8 * min(per_view, min(n for _, n in seen))
    runs = tiny.image_runs(row, parts.image_token_id)
    between = backend.tokenizer.decode(row[runs[3][0] + runs[3][1] : runs[4][0]])
    assert "frontleft" in between.replace(" ", "")
