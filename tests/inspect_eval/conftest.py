"""inspect_ai fixtures: scripted answers keyed by episode and round, given to inspect's
``mockllm/model`` or served by a local OpenAI-compatible server on 127.0.0.1."""

from __future__ import annotations

import json
import re
import threading
from collections.abc import Iterator, Mapping, Sequence
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("inspect_ai")

from inspect_ai.model import ChatMessage, ModelOutput, ModelUsage

EPISODES = {"task": "standard_pick_place,tower_stacking", "seeds": "0", "resolution": 64}
"""Two tasks (two suites) × seed 0 × both instructions at 64 px: four episodes."""

Script = Mapping[str, Sequence[str]]
"""Episode key → the answer of each round (round 0 first)."""


@pytest.fixture(autouse=True)
def _private_results(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    """Snapshots and sample PNGs in one session-wide folder, never under the repo's results/."""
    root = tmp_path_factory.getbasetemp() / "inspect-results"
    monkeypatch.setenv("VLM_BENCH_RESULTS_DIR", str(root / "results"))
    monkeypatch.setenv("VLM_BENCH_SNAPSHOT_CACHE", str(root / "snapshots"))


def episode_of(user_texts: Sequence[str], keys: Mapping[str, str]) -> str:
    """The episode a conversation belongs to: its first user turn's text identifies it."""
    return keys["\n".join(user_texts)]


NOTE = re.compile(r"^\[\w+ view of that moment, not shown again\]$")
"""What a replan's history shows in place of an earlier round's image."""


def first_user_text(messages: Sequence[ChatMessage]) -> list[str]:
    """The text parts of the first user message (inspect messages), images' notes left out:
    the same for round 0 and for the history a replan carries."""
    user = next(m for m in messages if m.role == "user")
    content = user.content
    if isinstance(content, str):
        return [content]
    return [c.text for c in content if c.type == "text" and not NOTE.match(c.text)]


def scripted_mockllm(script: Script, keys: Mapping[str, str]) -> Any:
    """A ``custom_outputs`` callable for ``mockllm/model``: the script's answer to the
    conversation's episode, round = assistant turns so far (usage set: no tokenizer download)."""

    def answer(messages: list[ChatMessage], *_: Any) -> ModelOutput:
        key = episode_of(first_user_text(messages), keys)
        round_index = sum(1 for m in messages if m.role == "assistant")
        output = ModelOutput.from_content(model="mockllm", content=script[key][round_index])
        return output.model_copy(
            update={"usage": ModelUsage(input_tokens=1, output_tokens=1, total_tokens=2)}
        )

    return answer


class FakeOpenAI:
    """Chat completions on 127.0.0.1 answering from a script; records every request body."""

    def __init__(self, script: Script, keys: Mapping[str, str]) -> None:
        self.received: list[dict[str, Any]] = []
        lock = threading.Lock()
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:
                pass

            def do_POST(self) -> None:
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                with lock:
                    server.received.append(body)
                messages = body["messages"]
                user = next(m for m in messages if m["role"] == "user")["content"]
                texts = (
                    [user]
                    if isinstance(user, str)
                    else [
                        p["text"] for p in user if p["type"] == "text" and not NOTE.match(p["text"])
                    ]
                )
                round_index = sum(1 for m in messages if m["role"] == "assistant")
                try:
                    answer = script[episode_of(texts, keys)][round_index]
                except (KeyError, IndexError) as exc:  # a 400 fails the test, never retried
                    self._reply(400, {"error": {"message": f"unscripted: {exc}", "type": "x"}})
                    return
                payload = {
                    "id": "c", "object": "chat.completion", "created": 0, "model": body["model"],
                    "choices": [{"index": 0, "finish_reason": "stop", "message": {
                        "role": "assistant", "content": answer}}],
                    "usage": {"prompt_tokens": 10, "completion_tokens": 5, "total_tokens": 15},
                }  # fmt: skip
                self._reply(200, payload)

            def _reply(self, status: int, payload: dict[str, Any]) -> None:
                data = json.dumps(payload).encode()
                self.send_response(status)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(data)))
                self.end_headers()
                self.wfile.write(data)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)

    def __enter__(self) -> FakeOpenAI:
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()


def serve(script: Script, keys: Mapping[str, str]) -> Iterator[FakeOpenAI]:
    """Run a :class:`FakeOpenAI` for the duration of a ``with`` block's generator."""
    with FakeOpenAI(script, keys) as server:
        yield server


def png_bytes(image: str) -> bytes:
    """The PNG bytes of an inspect image reference (a file path or a data URL)."""
    if image.startswith("data:"):
        import base64

        return base64.b64decode(image.split(",", 1)[1])
    return Path(image).read_bytes()
