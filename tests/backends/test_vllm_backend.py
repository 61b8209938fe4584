"""The vllm backend's message and sampling construction, against a stand-in ``vllm`` module."""

from __future__ import annotations

import json
import sys
import time
import types
from pathlib import Path
from typing import Any

import pytest

from vlm_bench.backends import resolve_backend
from vlm_bench.backends.hf_decoding import hf_generate_kwargs
from vlm_bench.backends.messages import data_url, openai_messages
from vlm_bench.backends.vllm_backend import DEFAULT_MAX_MODEL_LEN, VllmBackend, sampling_kwargs
from vlm_bench.errors import ConfigError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, ImagePart, TextPart

PNG = b"\x89PNG\r\n\x1a\nbody"


def _request(rid: str, schema: dict[str, Any] | None = None) -> GenerationRequest:
    return GenerationRequest(
        id=rid,
        system="sys",
        user=(TextPart(text="uav:"), ImagePart(view="uav", png=PNG), TextPart(text="go")),
        json_schema=schema,
    )


def _fake_vllm(calls: dict[str, Any], *, structured: bool) -> types.ModuleType:
    """A stand-in for the parts of vllm the backend touches."""
    mod = types.ModuleType("vllm")
    params_mod = types.ModuleType("vllm.sampling_params")

    class Params:
        def __init__(self, **kwargs: Any) -> None:
            self.kwargs = kwargs

    if structured:
        params_mod.StructuredOutputsParams = Params  # type: ignore[attr-defined]
    else:
        params_mod.GuidedDecodingParams = Params  # type: ignore[attr-defined]

    class Completion:
        def __init__(self, text: str) -> None:
            self.text, self.token_ids, self.finish_reason = text, [1, 2, 3], "stop"

    class Output:
        def __init__(self, text: str) -> None:
            self.prompt_token_ids, self.outputs = list(range(10)), [Completion(text)]

    class LLM:
        def __init__(self, **kwargs: Any) -> None:
            calls["engine"] = kwargs

        def chat(self, messages: list[Any], sampling_params: list[Any], use_tqdm: bool) -> Any:
            calls.setdefault("chat", []).append((messages, sampling_params))
            return [Output(f"out{i}") for i in range(len(messages))]

    mod.LLM = LLM  # type: ignore[attr-defined]
    mod.SamplingParams = Params  # type: ignore[attr-defined]
    mod.sampling_params = params_mod  # type: ignore[attr-defined]
    return mod


def test_openai_messages_put_images_in_order_as_data_urls() -> None:
    system, user = openai_messages(_request("a"))
    assert system == {"role": "system", "content": "sys"}
    assert user["content"] == [
        {"type": "text", "text": "uav:"},
        {"type": "image_url", "image_url": {"url": data_url(PNG)}},
        {"type": "text", "text": "go"},
    ]
    [merged] = openai_messages(_request("a"), system_role=False)
    assert merged["role"] == "user" and merged["content"][0] == {"type": "text", "text": "sys"}


CONFIGS = [
    GenerationConfig(),
    GenerationConfig(repetition_penalty=1.05, max_new_tokens=64),
    GenerationConfig(temperature=0.7, top_p=0.8, top_k=20, seed=3, repetition_penalty=1.1),
]
HF_TO_VLLM = {
    "max_new_tokens": "max_tokens",
    "repetition_penalty": "repetition_penalty",
    "temperature": "temperature",
    "top_p": "top_p",
    "top_k": "top_k",
}


@pytest.mark.parametrize("config", CONFIGS, ids=["greedy", "greedy-penalty", "sampled"])
def test_hf_and_vllm_decode_with_the_same_settings(config: GenerationConfig) -> None:
    """Every decoding setting reaches both backends, with the same value (greedy: vLLM's
    temperature 0 and no top-p/top-k limit is hf's do_sample=False)."""
    hf, vllm = hf_generate_kwargs(config), sampling_kwargs(config)
    assert set(config.decoding()) <= {*HF_TO_VLLM, "seed"}
    for hf_name, vllm_name in HF_TO_VLLM.items():
        if hf_name in config.decoding():
            assert hf[hf_name] == vllm[vllm_name] == config.decoding()[hf_name]
    assert hf["do_sample"] is (not config.greedy) and hf["num_beams"] == 1
    if config.greedy:
        assert (vllm["temperature"], vllm["top_p"], vllm["top_k"]) == (0.0, 1.0, -1)
        assert "seed" not in vllm
    else:
        assert vllm["seed"] == config.seed


def test_decoding_names_every_setting_that_shapes_tokens() -> None:
    """A field added to GenerationConfig must be routed to the backends (or listed here)."""
    sampled = GenerationConfig(temperature=0.5).decoding()
    assert set(GenerationConfig.model_fields) - set(sampled) == {"constrained", "batch_size"}


@pytest.mark.parametrize("structured", [True, False])
def test_generate_batches_through_llm_chat(
    monkeypatch: pytest.MonkeyPatch, structured: bool
) -> None:
    calls: dict[str, Any] = {}
    monkeypatch.setitem(sys.modules, "vllm", _fake_vllm(calls, structured=structured))
    backend = resolve_backend("vllm/org/model", {"tensor_parallel_size": "2", "max_images": "4"})
    assert isinstance(backend, VllmBackend)
    assert calls["engine"]["model"] == "org/model"
    assert calls["engine"]["tensor_parallel_size"] == 2
    assert calls["engine"]["limit_mm_per_prompt"] == {"image": 4}
    schema = {"type": "array"}
    config = GenerationConfig(batch_size=2, constrained=True, max_new_tokens=32)
    results = backend.generate([_request(str(i), schema) for i in range(3)], config)
    assert [r.text for r in results] == ["out0", "out1", "out0"]
    assert results[0].prompt_tokens == 10 and results[0].completion_tokens == 3
    assert [len(m) for m, _ in calls["chat"]] == [2, 1]
    messages, params = calls["chat"][0]
    assert messages[0] == openai_messages(_request("0", schema))
    key = "structured_outputs" if structured else "guided_decoding"
    assert params[0].kwargs["max_tokens"] == 32 and params[0].kwargs[key].kwargs == {"json": schema}


def test_engine_defaults_and_processor_arguments(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: dict[str, Any] = {}
    monkeypatch.setitem(sys.modules, "vllm", _fake_vllm(calls, structured=True))
    resolve_backend("vllm/org/model", {})
    assert calls["engine"]["max_model_len"] == DEFAULT_MAX_MODEL_LEN
    assert "mm_processor_kwargs" not in calls["engine"]
    resolve_backend(
        "vllm/org/model",
        {"mm_processor_kwargs": '{"max_crops": 4}', "hf_overrides": '{"architectures": ["X"]}'},
    )
    assert calls["engine"]["mm_processor_kwargs"] == {"max_crops": 4}
    assert calls["engine"]["hf_overrides"] == {"architectures": ["X"]}
    with pytest.raises(ConfigError, match=r"mm_processor_kwargs.*JSON"):
        resolve_backend("vllm/org/model", {"mm_processor_kwargs": "max_crops=4"})


@pytest.mark.parametrize(
    ("model_type", "args", "expected"),
    [
        ("qwen2_5_vl", {"max_pixels": "200704"}, {"max_pixels": 200704}),
        (
            "qwen3_vl",
            {"min_pixels": "1024", "max_pixels": "4096"},
            {"min_pixels": 1024, "max_pixels": 4096},
        ),
        ("internvl_chat", {"max_tiles": "4"}, {"max_dynamic_patch": 4}),
    ],
)
def test_pixel_and_tile_limits_reach_the_engine(
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    model_type: str,
    args: dict[str, str],
    expected: dict[str, int],
) -> None:
    (tmp_path / "config.json").write_text(json.dumps({"model_type": model_type}))
    calls: dict[str, Any] = {}
    monkeypatch.setitem(sys.modules, "vllm", _fake_vllm(calls, structured=True))
    resolve_backend(f"vllm/{tmp_path}", args)
    assert calls["engine"]["mm_processor_kwargs"] == expected


@pytest.mark.parametrize(
    ("model_type", "args"),
    [("llava", {"max_pixels": "1000"}), ("qwen2_5_vl", {"max_tiles": "2"})],
)
def test_a_limit_the_model_has_not_is_an_error(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, model_type: str, args: dict[str, str]
) -> None:
    (tmp_path / "config.json").write_text(json.dumps({"model_type": model_type}))
    calls: dict[str, Any] = {}
    monkeypatch.setitem(sys.modules, "vllm", _fake_vllm(calls, structured=True))
    with pytest.raises(ConfigError, match=f"no such limit for model type '{model_type}'"):
        resolve_backend(f"vllm/{tmp_path}", args)
    assert "engine" not in calls  # refused before the engine starts


def test_each_result_gets_its_share_of_the_batch_time(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: dict[str, Any] = {}
    fake = _fake_vllm(calls, structured=True)
    chat = fake.LLM.chat  # type: ignore[attr-defined]

    def slow_chat(self: Any, *args: Any, **kwargs: Any) -> Any:
        time.sleep(0.2)
        return chat(self, *args, **kwargs)

    fake.LLM.chat = slow_chat  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "vllm", fake)
    backend = resolve_backend("vllm/org/model", {})
    results = backend.generate([_request(str(i)) for i in range(4)], GenerationConfig(batch_size=4))
    batch = results[0].batch_latency_s
    assert batch is not None and batch >= 0.2
    assert all(r.batch_latency_s == batch for r in results)
    assert sum(r.latency_s for r in results) == pytest.approx(batch)
