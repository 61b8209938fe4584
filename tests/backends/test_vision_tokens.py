"""Visual tokens per view, computed from each model card's settings (``vision``): the rules
agree with the real processors on the tiny models (four views and one view), the cards' numbers
hold at 448 px, and every recipe fits its context length."""

from __future__ import annotations

import importlib.util
import io
import json
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from vlm_bench.catalog.model_cards import model_card, model_cards
from vlm_bench.types.model_card import PROMPT_TEXT_TOKENS

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("card", "size", "four", "one"),
    [
        ("qwen2.5-vl-7b", 448, 256, 256),
        ("qwen3-vl-8b", 448, 196, 196),
        ("glm-4.1v-9b-thinking", 448, 256, 256),
        ("internvl3.5-8b", 448, 256, 256),
        ("internvl3.5-8b", 896, 5 * 256, 5 * 256),  # 2x2 tiles and a thumbnail
        ("llava-onevision-7b", 448, 730, 3699),  # one tile each of several; anyres alone
        ("molmo-7b-d", 448, 580, 580),
        ("molmo-7b-d", 336, 316, 316),  # one crop and the whole view
        ("glm-4v-9b", 448, 1602, 1602),
    ],
)
def test_card_token_counts(card: str, size: int, four: int, one: int) -> None:
    vision = model_card(card).vision
    assert (vision.tokens(size, 4), vision.tokens(size, 1)) == (four, one)


def test_every_recipe_fits_its_context_length() -> None:
    for card in model_cards().values():
        limit = int((card.vllm_args or {}).get("max_model_len", 32768))
        budget = card.token_budget()
        used = PROMPT_TEXT_TOKENS + budget.recipe_image_tokens + card.max_new_tokens
        assert used <= limit, (card.name, used, limit)
    molmo = model_card("molmo-7b-d")
    four = PROMPT_TEXT_TOKENS + 4 * molmo.vision.tokens(448, 4) + molmo.max_new_tokens
    assert four > 4096  # why its recipe shows one view
    assert molmo.token_budget().recipe_views == 1


def test_models_json_shows_tokens_per_view(cli: Any) -> None:
    for name in model_cards():
        data = json.loads(cli.invoke("models", name, "--json"))
        budget = data["tokens_per_view"]
        assert budget["four_views"] > 0 and budget["one_view"] > 0 and budget["resolution"] == 448
    llava = json.loads(cli.invoke("models", "llava-onevision-7b", "--json"))["tokens_per_view"]
    assert (llava["four_views"], llava["one_view"], llava["recipe_image_tokens"]) == (
        730,
        3699,
        2920,
    )


def test_sampling_is_a_preset_beside_greedy(cli: Any) -> None:
    qwen = model_card("qwen3-vl-8b")
    assert qwen.sampling is not None and qwen.sampling.temperature == 0.7
    assert "--sampling" in cli.invoke("models", "qwen3-vl-8b")
    from vlm_bench.cli.run_cmds import sampling_settings
    from vlm_bench.errors import ConfigError

    assert sampling_settings("qwen3-vl-8b", 0.0) == {
        "temperature": 0.7, "top_p": 0.8, "top_k": 20, "repetition_penalty": 1.0,
    }  # fmt: skip
    with pytest.raises(ConfigError, match="not both"):
        sampling_settings("qwen3-vl-8b", 0.5)
    with pytest.raises(ConfigError, match="no model card"):
        sampling_settings("mock", 0.0)


# The tiny models: the card's rule with the tiny processor's settings, against the processor.
TINY_SETTINGS: dict[str, dict[str, Any]] = {
    "qwen2_5_vl": {"patch": 14, "merge": 2, "min_pixels": 28 * 28, "max_pixels": 28 * 28 * 16},
    "qwen3_vl": {"patch": 16, "merge": 2, "min_pixels": 32 * 32, "max_pixels": 32 * 32 * 16},
    "glm4v": {"patch": 14, "merge": 2, "min_pixels": 28 * 28, "max_pixels": 28 * 28 * 16},
    "internvl": {"tile": 32, "tokens_per_tile": 4, "max_tiles": 4},
    "llava_onevision": {
        "tile": 32,
        "tokens_per_tile": 16,
        "pinpoints": ((32, 32), (32, 64), (64, 32), (64, 64)),
    },
}
"""What ``benchmarks/tiny_vlms.py`` builds each processor with."""


def _tiny() -> ModuleType:
    pytest.importorskip("torch")
    pytest.importorskip("transformers")
    spec = importlib.util.spec_from_file_location("tiny_vlms", ROOT / "benchmarks/tiny_vlms.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("tiny_vlms", module)
    spec.loader.exec_module(module)
    return module


def _count(tiny: ModuleType, processor: Any, image_id: int, views: int, size: int) -> int:
    """Image tokens per view of a request with the first ``views`` views, encoded alone."""
    from PIL import Image

    from vlm_bench.backends.hf import hf_messages
    from vlm_bench.types.generation import GenerationRequest

    full = tiny.four_view_requests("", 1, size)[0]
    parts = [*full.user[: 2 * views], full.user[-1]]  # (label, image) pairs, instruction
    request = GenerationRequest(id="x", system="", user=tuple(parts))
    images = [Image.open(io.BytesIO(p.png)).convert("RGB") for p in request.images()]
    text = processor.apply_chat_template(
        hf_messages(request, images), add_generation_prompt=True, tokenize=False
    )
    encoded = processor(text=[text], images=[images], return_tensors="pt")
    return int((encoded["input_ids"] == image_id).sum()) // views


@pytest.mark.parametrize("arch_name", sorted(TINY_SETTINGS))
def test_card_rules_match_the_tiny_processors(arch_name: str) -> None:
    tiny = _tiny()
    arch = next(a for a in tiny.ARCHS if a.name == arch_name)
    built = arch.build(["UAV camera (uav): pick the gray cube", "[]"] * 3)
    processor = built.in_memory_processor()
    rule = model_card(arch.card).vision.model_copy(update=TINY_SETTINGS[arch_name])
    for size in (64, 112):
        for views in (4, 1):
            seen = _count(tiny, processor, built.image_token_id, views, size)
            assert rule.tokens(size, views) == seen, (arch_name, size, views)
