"""Closed-loop replans as conversations: the OpenAI messages of round 2 (fake server, a real
closed-loop run) and the vLLM request (``llm.chat`` messages)."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

import pytest

pytest.importorskip("openai")

import vlm_bench.api as api
from tests.conftest import module_from_file
from vlm_bench.backends.messages import openai_messages
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.generation import GenerationRequest, ImagePart, TextPart, Turn

PNG = b"\x89PNG\r\n\x1a\n" + b"fake"


def _openai_tests() -> ModuleType:
    return module_from_file(
        "_openai_backend_tests", Path(__file__).with_name("test_openai_backend.py")
    )


FakeServer = _openai_tests().FakeServer


def _kinds(message: dict[str, object]) -> list[str]:
    content = message["content"]
    return [p["type"] for p in content] if isinstance(content, list) else ["str"]  # type: ignore[index]


@pytest.mark.parametrize("history", ["text", "images"])
def test_round_two_sends_the_whole_conversation(tmp_path: Path, history: str) -> None:
    with FakeServer() as server:  # answers every request with one move left: never done
        result = api.run(
            out=tmp_path / "run",
            execution=ExecutionOptions(workers=0),
            model="openai/m",
            backend_args={"base_url": server.url},
            tasks=("standard_pick_place",),
            seeds=(0,),
            instructions=("explicit",),
            resolution=32,
            k_shot=0,
            loop="closed",
            max_rounds=2,
            history=history,
        )
    (record,) = result.records
    assert record.loop is not None and record.loop.rounds_used == 3
    assert len(server.received) == 3
    messages = server.received[2]["messages"]
    assert [m["role"] for m in messages] == [
        "system",
        "user",
        "assistant",
        "user",
        "assistant",
        "user",
    ]
    assert messages[2]["content"] == record.raw_output
    assert record.rounds is not None and messages[4]["content"] == record.rounds[0].raw_output
    earlier = 4 if history == "images" else 0
    assert _kinds(messages[1]).count("image_url") == earlier
    assert _kinds(messages[3]).count("image_url") == earlier
    assert _kinds(messages[5]).count("image_url") == 4  # the views of the state now
    assert "Steps executed so far" in messages[5]["content"][0]["text"]
    round_two = server.received[2]["messages"][5]["content"]
    assert any("failed" in p.get("text", "") or "done" in p.get("text", "") for p in round_two)


def test_vllm_chat_messages_carry_the_history_in_order() -> None:
    """The vllm backend sends ``openai_messages`` to ``llm.chat`` (tests/backends/
    test_vllm_backend.py): earlier turns sit between the system message and the user turn."""
    request = GenerationRequest(
        id="k#r1",
        system="You plan.",
        history=(
            Turn(role="user", content=(TextPart(text="first"), ImagePart(view="uav", png=PNG))),
            Turn(role="assistant", content=(TextPart(text="[]"),)),
        ),
        user=(TextPart(text="again"), ImagePart(view="uav", png=PNG)),
    )
    system, first, answer, now = openai_messages(request)
    assert system == {"role": "system", "content": "You plan."}
    assert [p["type"] for p in first["content"]] == ["text", "image_url"]
    assert answer == {"role": "assistant", "content": "[]"}
    assert now["content"][0] == {"type": "text", "text": "again"}
    assert [p.view for p in request.images()] == ["uav", "uav"]
    merged = openai_messages(request, system_role=False)
    assert merged[0]["content"][0] == {"type": "text", "text": "You plan."}
    assert merged[2]["content"][0] == {"type": "text", "text": "again"}
