"""Every architecture of the paper's VLMs (plus LLaVA), as a tiny random-weight model built from
config with a locally trained tokenizer (no hub): it loads as the card says, the four labelled
views reach it (image tokens counted, each view after its label), and greedy batch 8 equals
batch 1. ``vlm-bench run --model <folder>`` runs end to end where the processor can be saved
and loaded: LLaVA here; the five whose processors hold a torchvision video processor skip
without torchvision (``benchmarks/architectures_gpu.py`` runs them all on a GPU machine).
"""

from __future__ import annotations

import importlib.util
import io
import json
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("transformers")

from PIL import Image  # noqa: E402

from vlm_bench.backends.hf import HfBackend  # noqa: E402
from vlm_bench.catalog.model_cards import model_cards  # noqa: E402
from vlm_bench.types.generation import (  # noqa: E402
    GenerationConfig,
    GenerationRequest,
    ImagePart,
)
from vlm_bench.types.prompt import TextPart  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
VIEWS = {"uav": "UAV camera", "wrist": "Wrist camera", "overhead": "Overhead camera"}
VIEWS["side"] = "Side camera"
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
    from vlm_bench.episodes import make_episode
    from vlm_bench.prompting import build_prompt
    from vlm_bench.types.run import RunConfig

    episode = make_episode("standard_pick_place", 0)
    config = RunConfig(model="mock", images=False, k_shot=0).prompt_config("explicit")
    return build_prompt(episode, {}, config).to_request("x").system


@pytest.fixture(scope="module")
def corpus(system_prompt: str) -> list[str]:
    plan = '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}]'
    return [system_prompt, *VIEWS.values(), plan, "pick the gray cube"] * 3


@pytest.fixture(scope="module", params=sorted(ARCHS))
def built(request: pytest.FixtureRequest, corpus: list[str]) -> Iterator[tuple[Any, Any]]:
    arch = ARCHS[request.param]
    yield arch, arch.build(corpus)


def _png(color: tuple[int, int, int], size: int = 112) -> bytes:
    buf = io.BytesIO()
    Image.new("RGB", (size, size), color).save(buf, format="PNG")
    return buf.getvalue()


def _requests(system: str, n: int) -> list[GenerationRequest]:
    """The run's request layout: each view's label, then its image; then the instruction."""
    out: list[GenerationRequest] = []
    for i in range(n):
        parts: list[TextPart | ImagePart] = []
        for k, (view, title) in enumerate(VIEWS.items()):
            color = (60 * k, 255 - 40 * i, 30 * i)
            parts += [TextPart(text=f"{title} ({view}):\n"), ImagePart(view=view, png=_png(color))]
        parts.append(TextPart(text=f"Instruction: put object {i} in the basket."))
        out.append(GenerationRequest(id=f"r{i}", system=system, user=tuple(parts)))
    return out


def _image_runs(ids: list[int], image_id: int) -> list[tuple[int, int]]:
    """(start, length) of each run of image tokens."""
    runs: list[tuple[int, int]] = []
    for i, tok in enumerate(ids):
        if tok == image_id:
            if runs and runs[-1][0] + runs[-1][1] == i:
                runs[-1] = (runs[-1][0], runs[-1][1] + 1)
            else:
                runs.append((i, 1))
    return runs


def _tokens_per_image(processor: Any, image_id: int, system: str) -> int:
    """Image tokens the processor gives each view of one four-view request encoded alone (all
    views share a size; LLaVA-OneVision gives an image fewer tokens when it is one of many)."""
    from vlm_bench.backends.hf import hf_messages

    request = _requests(system, 1)[0]
    images = [Image.open(io.BytesIO(p.png)).convert("RGB") for p in request.images()]
    text = processor.apply_chat_template(
        hf_messages(request, images), add_generation_prompt=True, tokenize=False
    )
    encoded = processor(text=[text], images=[images], return_tensors="pt")
    total = int((encoded["input_ids"] == image_id).sum())
    assert total % len(VIEWS) == 0
    return total // len(VIEWS)


def _check_views_reach_the_model(
    rows: list[list[int]], tokenizer: Any, image_id: int, per_image: int
) -> None:
    for ids in rows:
        runs = _image_runs(ids, image_id)
        assert [length for _, length in runs] == [per_image] * len(VIEWS)
        for (start, _), view in zip(runs, VIEWS, strict=True):
            before = tokenizer.decode(ids[max(0, start - 12) : start])
            assert f"({view}):" in before, (view, before)


def _spy_on_encode(monkeypatch: pytest.MonkeyPatch) -> list[list[int]]:
    rows: list[list[int]] = []
    real = HfBackend._encode

    def encode(self: HfBackend, batch: Any) -> Any:
        inputs = real(self, batch)
        mask = inputs["attention_mask"].bool()
        rows.extend(ids[m].tolist() for ids, m in zip(inputs["input_ids"], mask, strict=True))
        return inputs

    monkeypatch.setattr(HfBackend, "_encode", encode)
    return rows


def test_built_from_config_loads_as_its_card_says(built: tuple[Any, Any], tmp_path: Path) -> None:
    from transformers import AutoModelForImageTextToText

    arch, parts = built
    parts.model.save_pretrained(tmp_path)
    loaded = AutoModelForImageTextToText.from_pretrained(tmp_path)
    assert type(loaded).__name__ == arch.architecture
    if arch.card is not None:
        assert model_cards()[arch.card].architecture == arch.architecture


def test_four_labelled_views_reach_the_model_and_batches_agree(
    built: tuple[Any, Any], system_prompt: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Through the hf backend's own encode and generate (the processor built around its PIL
    image processor, without the video processor, where torchvision is missing)."""
    arch, parts = built
    processor = parts.in_memory_processor()
    backend = HfBackend.from_loaded(arch.name, processor, parts.model)
    rows = _spy_on_encode(monkeypatch)
    requests = _requests(system_prompt, 8)
    one = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=1))
    eight = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=8))
    assert all(r.error is None for r in one + eight)
    assert [r.text for r in eight] == [r.text for r in one]
    per_image = _tokens_per_image(processor, parts.image_token_id, system_prompt)
    assert per_image > 0
    _check_views_reach_the_model(rows, backend.tokenizer, parts.image_token_id, per_image)


def _cli_run(out: Path, model: Path, batch_size: int) -> None:
    from typer.testing import CliRunner

    from vlm_bench.cli.main import _register, app

    if not any(c.name == "run" for c in app.registered_commands):
        _register()
    args = ["run", "--model", str(model), "--task", "standard_pick_place", "--seeds", "0-3"]
    args += ["--resolution", "112", "--k-shot", "0", "--no-execute", "--no-progress"]
    args += ["--max-new-tokens", "6", "--batch-size", str(batch_size), "--out", str(out)]
    result = CliRunner().invoke(app, args, catch_exceptions=False)
    assert result.exit_code == 0, result.output


def _outputs(run: Path) -> dict[str, str]:
    lines = (run / "records.jsonl").read_text().splitlines()
    return {r["key"]: r["raw_output"] for r in map(json.loads, lines)}


def test_vlm_bench_run_end_to_end(
    built: tuple[Any, Any], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    arch, parts = built
    if arch.video_processor and not tiny.has_torchvision():
        pytest.skip(f"{arch.name}: {NO_TORCHVISION}")
    model = parts.save(tmp_path / arch.name)
    rows = _spy_on_encode(monkeypatch)
    _cli_run(tmp_path / "batch1", model, 1)
    _cli_run(tmp_path / "batch8", model, 8)
    one, eight = _outputs(tmp_path / "batch1"), _outputs(tmp_path / "batch8")
    assert len(one) == 8 and eight == one
    processor = parts.processor()
    per_image = _tokens_per_image(processor, parts.image_token_id, "")
    assert len(rows) == 16
    _check_views_reach_the_model(rows, processor.tokenizer, parts.image_token_id, per_image)
