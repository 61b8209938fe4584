"""The hf backend on a tiny random-weight LLaVA built locally (CPU, no hub access)."""

from __future__ import annotations

import io
import json
import os
from pathlib import Path
from typing import Any

import pytest

torch = pytest.importorskip("torch")
transformers = pytest.importorskip("transformers")

from PIL import Image  # noqa: E402

from vlm_bench.backends import resolve_backend  # noqa: E402
from vlm_bench.backends.hf import HfBackend, hf_messages  # noqa: E402
from vlm_bench.errors import ConfigError  # noqa: E402
from vlm_bench.types.generation import (  # noqa: E402
    GenerationConfig,
    GenerationRequest,
    GenerationResult,
    ImagePart,
    TextPart,
)

os.environ["HF_HUB_OFFLINE"] = "1"

CHAT_TEMPLATE = (
    "{% for m in messages %}<|{{ m['role'] }}|>{% if m['content'] is string %}{{ m['content'] }}"
    "{% else %}{% for c in m['content'] %}{% if c['type'] == 'image' %}<image>"
    "{% elif c['type'] == 'text' %}{{ c['text'] }}{% endif %}{% endfor %}{% endif %}</s>"
    "{% endfor %}{% if add_generation_prompt %}<|assistant|>{% endif %}"
)
IMAGE_TOKENS = 16  # (32 px / 8 px patches)^2, CLS dropped by the "default" feature strategy


def _build_tiny_llava(out: Path) -> Path:
    from tokenizers import Tokenizer, decoders, models, pre_tokenizers, trainers
    from transformers import (
        CLIPImageProcessor,
        CLIPVisionConfig,
        LlamaConfig,
        LlavaConfig,
        LlavaForConditionalGeneration,
        LlavaProcessor,
        PreTrainedTokenizerFast,
    )

    specials = [
        "<pad>",
        "<s>",
        "</s>",
        "<unk>",
        "<image>",
        "<|system|>",
        "<|user|>",
        "<|assistant|>",
    ]
    bpe = Tokenizer(models.BPE(unk_token="<unk>"))
    bpe.pre_tokenizer = pre_tokenizers.ByteLevel(add_prefix_space=False)
    bpe.decoder = decoders.ByteLevel()
    corpus = [
        '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}]',
        "pick the gray cube and place it in the yellow basket",
    ] * 20
    bpe.train_from_iterator(
        corpus,
        trainers.BpeTrainer(
            vocab_size=320,
            special_tokens=specials,
            initial_alphabet=pre_tokenizers.ByteLevel.alphabet(),
        ),
    )
    tokenizer = PreTrainedTokenizerFast(
        tokenizer_object=bpe,
        bos_token="<s>",
        eos_token="</s>",
        pad_token="<pad>",
        unk_token="<unk>",
        extra_special_tokens={"image_token": "<image>"},
    )
    processor = LlavaProcessor(
        image_processor=CLIPImageProcessor(
            size={"shortest_edge": 32}, crop_size={"height": 32, "width": 32}
        ),
        tokenizer=tokenizer,
        patch_size=8,
        vision_feature_select_strategy="default",
        num_additional_image_tokens=1,
        chat_template=CHAT_TEMPLATE,
    )
    config = LlavaConfig(
        vision_config=CLIPVisionConfig(
            hidden_size=32,
            intermediate_size=64,
            num_hidden_layers=1,
            num_attention_heads=2,
            image_size=32,
            patch_size=8,
            projection_dim=32,
        ),
        text_config=LlamaConfig(
            hidden_size=32,
            intermediate_size=64,
            num_hidden_layers=1,
            num_attention_heads=2,
            num_key_value_heads=2,
            vocab_size=len(tokenizer),
            max_position_embeddings=2048,
            bos_token_id=tokenizer.bos_token_id,
            eos_token_id=tokenizer.eos_token_id,
            pad_token_id=tokenizer.pad_token_id,
        ),
        image_token_id=tokenizer.convert_tokens_to_ids("<image>"),
        vision_feature_select_strategy="default",
        vision_feature_layer=-1,
    )
    torch.manual_seed(0)
    model = LlavaForConditionalGeneration(config).eval()
    model.generation_config.pad_token_id = tokenizer.pad_token_id
    model.generation_config.eos_token_id = tokenizer.eos_token_id
    model.save_pretrained(out)
    processor.save_pretrained(out)
    return out


@pytest.fixture(scope="module")
def llava_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _build_tiny_llava(tmp_path_factory.mktemp("tiny-llava"))


@pytest.fixture(scope="module")
def backend(llava_dir: Path) -> HfBackend:
    built = resolve_backend(str(llava_dir), {})  # a local path selects hf
    assert isinstance(built, HfBackend)
    return built


def _png(color: tuple[int, int, int], size: int = 40) -> bytes:
    buf = io.BytesIO()
    Image.new("RGB", (size, size), color).save(buf, format="PNG")
    return buf.getvalue()


def _request(rid: str, n_images: int, instruction: str) -> GenerationRequest:
    parts: list[TextPart | ImagePart] = []
    for i in range(n_images):
        parts += [TextPart(text=f"view {i}:"), ImagePart(view=f"v{i}", png=_png((40 * i, 0, 0)))]
    parts.append(TextPart(text=instruction))
    return GenerationRequest(id=rid, system="You plan.", user=tuple(parts))


def _prompt_len(backend: HfBackend, request: GenerationRequest) -> int:
    """Token count of one request encoded alone (no padding)."""
    images = [Image.open(io.BytesIO(p.png)).convert("RGB") for p in request.images()]
    text = backend.processor.apply_chat_template(
        hf_messages(request, images), add_generation_prompt=True, tokenize=False
    )
    encoded = backend.processor(text=[text], images=[images], return_tensors="pt")
    return int(encoded["input_ids"].shape[1])


def test_batched_generation_counts_tokens(backend: HfBackend) -> None:
    requests = [_request("a", 2, "pick the cube"), _request("b", 1, "place it in the basket now")]
    config = GenerationConfig(max_new_tokens=12, batch_size=2)
    results = backend.generate(requests, config)
    assert [r.id for r in results] == ["a", "b"]
    for req, res in zip(requests, results, strict=True):
        assert res.error is None and isinstance(res.text, str)
        assert res.prompt_tokens == _prompt_len(backend, req)
        assert res.completion_tokens is not None and 1 <= res.completion_tokens <= 12
        assert res.finish_reason in {"stop", "length"}
        if res.finish_reason == "length":
            assert res.completion_tokens == 12
    assert backend.tokenizer.padding_side == "left"
    assert backend.model.dtype == torch.float32  # CPU default


def test_each_image_adds_its_placeholder_tokens(backend: HfBackend) -> None:
    with_image = _request("img", 1, "go")
    without = with_image.model_copy(
        update={"id": "txt", "user": tuple(p for p in with_image.user if p.type == "text")}
    )
    a, b = backend.generate([with_image, without], GenerationConfig(max_new_tokens=2))
    assert a.prompt_tokens is not None and b.prompt_tokens is not None
    assert a.prompt_tokens - b.prompt_tokens == IMAGE_TOKENS


def test_greedy_is_deterministic_and_batching_splits(backend: HfBackend) -> None:
    requests = [_request(str(i), 1, f"instruction number {i}") for i in range(3)]
    first = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=2))
    second = backend.generate(requests, GenerationConfig(max_new_tokens=6, batch_size=2))
    assert [r.text for r in first] == [r.text for r in second]
    assert [r.id for r in first] == ["0", "1", "2"]


def test_out_of_memory_halves_the_batch(
    backend: HfBackend, monkeypatch: pytest.MonkeyPatch
) -> None:
    real_run = HfBackend._run
    sizes: list[int] = []

    def run(self: HfBackend, batch: Any, config: GenerationConfig) -> list[GenerationResult]:
        sizes.append(len(batch))
        if len(batch) > 1 or batch[0].id == "doomed":
            raise torch.OutOfMemoryError("CUDA out of memory (simulated)")
        return real_run(self, batch, config)

    monkeypatch.setattr(HfBackend, "_run", run)
    requests = [_request("a", 1, "x y"), _request("doomed", 1, "z"), _request("c", 1, "w")]
    results = backend.generate(requests, GenerationConfig(max_new_tokens=3, batch_size=3))
    assert [r.id for r in results] == ["a", "doomed", "c"]
    assert results[0].error is None and results[2].error is None
    assert results[1].error is not None and "OutOfMemoryError" in results[1].error
    assert sizes[0] == 3


def test_constrained_decoding_follows_the_schema(backend: HfBackend) -> None:
    pytest.importorskip("xgrammar")
    directions = ["front", "left", "frontleft"]
    schema = {
        "type": "array",
        "minItems": 1,
        "maxItems": 1,
        "items": {
            "type": "object",
            "properties": {"tasktype": {"const": "UAV"}, "direction": {"enum": directions}},
            "required": ["tasktype", "direction"],
            "additionalProperties": False,
        },
    }
    requests = [
        _request("a", 1, "fly").model_copy(update={"json_schema": schema}),
        _request("b", 2, "fly somewhere else").model_copy(update={"json_schema": schema}),
    ]
    config = GenerationConfig(max_new_tokens=60, constrained=True, batch_size=2)
    for result in backend.generate(requests, config):
        assert result.error is None and result.finish_reason == "stop", result
        [step] = json.loads(result.text)
        assert step["tasktype"] == "UAV" and step["direction"] in directions


def test_each_result_gets_its_share_of_the_batch_time(backend: HfBackend) -> None:
    import time

    requests = [_request(str(i), 1, f"instruction number {i}") for i in range(4)]
    start = time.perf_counter()
    results = backend.generate(requests, GenerationConfig(max_new_tokens=4, batch_size=4))
    wall = time.perf_counter() - start
    assert sum(r.latency_s for r in results) <= wall  # was 4 x the batch time
    batch = results[0].batch_latency_s
    assert batch is not None and all(r.batch_latency_s == batch for r in results)
    assert sum(r.latency_s for r in results) == pytest.approx(batch)


def test_the_checkpoints_generation_config_does_not_decode(
    backend: HfBackend, llava_dir: Path, tmp_path: Path
) -> None:
    """A checkpoint whose generation_config penalises repeats (Qwen2.5-VL ships 1.05) decodes
    exactly as the same weights without it: the run's settings are the only ones."""
    import shutil

    shutil.copytree(llava_dir, tmp_path / "penalised")
    gen_file = tmp_path / "penalised" / "generation_config.json"
    gen = json.loads(gen_file.read_text())
    gen.update(repetition_penalty=50.0, no_repeat_ngram_size=1, top_k=1, do_sample=True)
    gen_file.write_text(json.dumps(gen))
    penalised = resolve_backend(str(tmp_path / "penalised"), {})
    assert isinstance(penalised, HfBackend)
    requests = [_request(str(i), 1, f"pick cube {i}") for i in range(3)]
    config = GenerationConfig(max_new_tokens=24, batch_size=3)
    plain_texts = [r.text for r in backend.generate(requests, config)]
    tokens = [backend.tokenizer.encode(t, add_special_tokens=False) for t in plain_texts]
    assert any(len(set(t)) < len(t) for t in tokens)  # greedy repeats: a penalty would show
    assert [r.text for r in penalised.generate(requests, config)] == plain_texts
    assert penalised.checkpoint_generation["repetition_penalty"] == 50.0  # and it is logged


def test_an_explicit_repetition_penalty_applies(backend: HfBackend) -> None:
    requests = [_request(str(i), 1, f"pick cube {i}") for i in range(3)]
    plain = backend.generate(requests, GenerationConfig(max_new_tokens=24, batch_size=3))
    strict = backend.generate(
        requests, GenerationConfig(max_new_tokens=24, batch_size=3, repetition_penalty=50.0)
    )
    assert [r.text for r in plain] != [r.text for r in strict]


def test_a_pixel_limit_on_a_fixed_size_processor_is_an_error(llava_dir: Path) -> None:
    with pytest.raises(ConfigError, match=r"-M max_pixels: .*CLIPImageProcessor.*no pixel or tile"):
        resolve_backend(str(llava_dir), {"max_pixels": "50176"})


def test_constrained_plans_close_within_the_budget(backend: HfBackend) -> None:
    """The plan schema bounds the steps, so the grammar lets the array close: no output is cut
    off by max_new_tokens (without maxItems a random model adds steps until it is)."""
    pytest.importorskip("xgrammar")
    from vlm_bench.parsing import parse_plan, plan_json_schema

    ids = ["gray_cube", "yellow_basket", "table"]
    schema = plan_json_schema(ids)
    requests = [
        _request(str(i), 1, f"put the cube in the basket {i}").model_copy(
            update={"json_schema": schema}
        )
        for i in range(2)
    ]
    config = GenerationConfig(max_new_tokens=1500, constrained=True, batch_size=2)
    for result in backend.generate(requests, config):
        assert result.finish_reason == "stop", result
        assert parse_plan(result.text, ids).tier == "valid"
