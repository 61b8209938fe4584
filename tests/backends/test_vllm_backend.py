"""The vllm backend's message and sampling construction, against a stand-in ``vllm`` module."""

from __future__ import annotations

import sys
import types
from typing import Any

import pytest

from vlm_bench.backends import resolve_backend
from vlm_bench.backends.messages import data_url, openai_messages
from vlm_bench.backends.vllm_backend import VllmBackend, sampling_kwargs
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, ImagePart
from vlm_bench.types.prompt import TextPart

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


def test_sampling_kwargs() -> None:
    assert sampling_kwargs(GenerationConfig()) == {
        "max_tokens": 512,
        "temperature": 0.0,
        "top_p": 1.0,
    }
    assert sampling_kwargs(GenerationConfig(temperature=0.5, seed=3))["seed"] == 3


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
