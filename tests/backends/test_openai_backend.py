"""The openai backend against a fake OpenAI-compatible server on 127.0.0.1 (loopback only).

The fake answers ``GET /models`` (the load-time check) and, when ``enforces_schema`` is set,
follows ``response_format`` for the structured-outputs probe, as vLLM or SGLang would; with it
unset it ignores the field, as ``transformers serve`` does.
"""

from __future__ import annotations

import base64
import json
import threading
import time
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

import pytest

pytest.importorskip("openai")

from vlm_bench.backends import resolve_backend
from vlm_bench.errors import ConfigError, VlmBenchError
from vlm_bench.types.generation import (
    GenerationConfig,
    GenerationRequest,
    ImagePart,
    TextPart,
)

PNG = b"\x89PNG\r\n\x1a\n" + b"fake-png-body"
FAST = {"backoff_s": "0.01", "backoff_max_s": "0.02"}


class FakeServer:
    """Scripted chat-completions endpoint that records what it receives."""

    def __init__(self) -> None:
        self.received: list[dict[str, Any]] = []
        self.fail_first = 0  # answer the first N calls with HTTP 500
        self.status = 500
        self.error: dict[str, Any] = {"error": {"message": "boom", "type": "server"}}
        self.sleep_s = 0.0
        self.barrier: threading.Barrier | None = None  # hold each request until N are in flight
        self.calls = 0
        self.model_lists = 0
        self.enforces_schema = True
        self.raw: tuple[str, bytes] | None = None  # answer 200 with this content type and body
        self.lock = threading.Lock()
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:  # keep test output quiet
                pass

            def do_GET(self) -> None:
                with server.lock:
                    server.model_lists += 1
                model = {"id": "m", "object": "model", "created": 0, "owned_by": "fake"}
                self._reply(200, {"object": "list", "data": [model]})

            def do_POST(self) -> None:
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                with server.lock:
                    server.calls += 1
                    call = server.calls
                    server.received.append(body)
                if server.sleep_s:
                    time.sleep(server.sleep_s)
                if server.barrier is not None:
                    try:
                        server.barrier.wait(timeout=20)
                    except threading.BrokenBarrierError:
                        self._reply(500, {"error": {"message": "not concurrent", "type": "x"}})
                        return
                if call <= server.fail_first:
                    self._reply(server.status, server.error)
                    return
                if server.raw is not None:
                    content_type, raw = server.raw
                    self.send_response(200)
                    self.send_header("Content-Type", content_type)
                    self.send_header("Content-Length", str(len(raw)))
                    self.end_headers()
                    self.wfile.write(raw)
                    return
                text = json.dumps([{"subtask": 0, "tasktype": "UAV", "direction": "left"}])
                schema = body.get("response_format", {}).get("json_schema", {}).get("schema", {})
                if server.enforces_schema and "probe" in schema.get("properties", {}):
                    text = json.dumps({"probe": schema["properties"]["probe"]["enum"][0]})
                content = body["messages"][-1]["content"]
                n_images = sum(
                    1 for part in content if isinstance(part, dict) and part["type"] == "image_url"
                )
                self._reply(
                    200,
                    {
                        "id": f"c{call}",
                        "object": "chat.completion",
                        "created": 0,
                        "model": body["model"],
                        "choices": [
                            {
                                "index": 0,
                                "finish_reason": "stop",
                                "message": {"role": "assistant", "content": text},
                            }
                        ],
                        "usage": {
                            "prompt_tokens": 100 + n_images,
                            "completion_tokens": 7,
                            "total_tokens": 107 + n_images,
                        },
                    },
                )

            def _reply(self, status: int, payload: dict[str, Any]) -> None:
                data = json.dumps(payload).encode()
                try:
                    self.send_response(status)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(data)))
                    self.end_headers()
                    self.wfile.write(data)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout test)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.httpd.block_on_close = False  # do not wait for handlers still sleeping
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"
        self.thread = threading.Thread(
            target=self.httpd.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True
        )

    def __enter__(self) -> FakeServer:
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()


@pytest.fixture
def server() -> Iterator[FakeServer]:
    with FakeServer() as srv:
        yield srv


def _request(rid: str, schema: dict[str, Any] | None = None) -> GenerationRequest:
    return GenerationRequest(
        id=rid,
        system="You plan.",
        user=(
            TextPart(text="UAV camera (uav):"),
            ImagePart(view="uav", png=PNG),
            TextPart(text="Side camera (side):"),
            ImagePart(view="side", png=PNG),
            TextPart(text="Instruction: go left."),
        ),
        json_schema=schema,
    )


def test_request_shape_and_results(server: FakeServer) -> None:
    backend = resolve_backend("openai/my-vlm", {"base_url": server.url, "concurrency": "3"})
    assert backend.max_concurrency == 3
    results = backend.generate([_request(f"r{i}") for i in range(5)], GenerationConfig())
    assert [r.id for r in results] == [f"r{i}" for i in range(5)]
    assert all(r.error is None and json.loads(r.text)[0]["direction"] == "left" for r in results)
    assert results[0].prompt_tokens == 102 and results[0].completion_tokens == 7
    assert results[0].finish_reason == "stop" and results[0].latency_s > 0
    body = server.received[0]
    assert body["model"] == "my-vlm" and body["max_tokens"] == 512
    assert body["temperature"] == 0.0 and "seed" not in body and "response_format" not in body
    system, user = body["messages"]
    assert system == {"role": "system", "content": "You plan."}
    kinds = [p["type"] for p in user["content"]]
    assert kinds == ["text", "image_url", "text", "image_url", "text"]
    url = user["content"][1]["image_url"]["url"]
    assert url.startswith("data:image/png;base64,")
    assert base64.b64decode(url.split(",", 1)[1]) == PNG
    backend.close()


def test_system_merge_sampling_and_json_schema(server: FakeServer) -> None:
    schema = {"type": "array", "items": {"type": "object"}}
    backend = resolve_backend(
        "openai/m", {"base_url": server.url, "system_role": "false", "image_detail": "low"}
    )
    config = GenerationConfig(temperature=0.7, seed=5, constrained=True, max_new_tokens=64)
    [result] = backend.generate([_request("a", schema)], config)
    assert result.error is None
    probe, body = server.received  # the structured-outputs check, then the request
    assert probe["response_format"]["json_schema"]["schema"]["required"] == ["probe"]
    assert [m["role"] for m in body["messages"]] == ["user"]
    assert body["messages"][0]["content"][0] == {"type": "text", "text": "You plan."}
    assert body["messages"][0]["content"][2]["image_url"]["detail"] == "low"
    assert body["seed"] == 5 and body["max_tokens"] == 64
    assert body["response_format"] == {
        "type": "json_schema",
        "json_schema": {"name": "plan", "schema": schema},
    }
    with pytest.raises(ConfigError, match=r"needs GenerationRequest\.json_schema"):
        backend.generate([_request("b")], config)


def test_transient_errors_are_retried(server: FakeServer) -> None:
    server.fail_first = 2
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "3", **FAST})
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert result.error is None and server.calls == 3


def test_exhausted_retries_are_recorded_not_raised(server: FakeServer) -> None:
    server.fail_first = 100
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "2", **FAST})
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert server.calls == 3 and result.text == ""
    assert result.error is not None and "InternalServerError 500" in result.error


PINNED = "Server is pinned to m; requested 'wrongname'"


@pytest.mark.parametrize("status", [400, 404, 409, 422])
@pytest.mark.parametrize(
    "body", [{"error": {"message": PINNED, "type": "invalid_request"}}, {"detail": PINNED}]
)
def test_client_errors_keep_the_servers_reason_and_are_not_retried(
    server: FakeServer, status: int, body: dict[str, Any]
) -> None:
    """The OpenAI API's error body and a FastAPI server's (``transformers serve``) alike."""
    server.fail_first, server.status, server.error = 100, status, body
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "3", **FAST})
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert server.calls == 1 and result.error is not None
    assert result.error.endswith(f" {status}: {PINNED}"), result.error


@pytest.mark.parametrize("status", [408, 429, 503])
def test_timeouts_rate_limits_and_server_errors_are_retried(
    server: FakeServer, status: int
) -> None:
    server.fail_first, server.status = 2, status
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "3", **FAST})
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert result.error is None and server.calls == 3


def test_timeouts_are_recorded(server: FakeServer) -> None:
    server.sleep_s = 1.0
    backend = resolve_backend(
        "openai/m", {"base_url": server.url, "timeout_s": "0.2", "retries": "1", **FAST}
    )
    start = time.perf_counter()
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert result.error is not None and "Timeout" in result.error
    assert server.calls == 2 and time.perf_counter() - start < 1.5


def test_requests_run_concurrently(server: FakeServer) -> None:
    """The server answers none of the 4 requests until all 4 are in flight at once: a client
    sending them one by one would get errors (no wall-clock limit, so load cannot fail it)."""
    server.barrier = threading.Barrier(4)
    backend = resolve_backend("openai/m", {"base_url": server.url, "concurrency": "4"})
    results = backend.generate([_request(f"r{i}") for i in range(4)], GenerationConfig())
    assert [r.error for r in results] == [None] * 4


def test_environment_fallbacks(server: FakeServer, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("VLM_BENCH_OPENAI_BASE_URL", server.url)
    monkeypatch.setenv("OPENAI_API_KEY", "sk-test")
    backend = resolve_backend("openai/m", {})
    [result] = backend.generate([_request("a")], GenerationConfig())
    assert result.error is None and server.calls == 1
    with pytest.raises(ConfigError, match="needs a model name"):
        resolve_backend("openai/", {})


def _closed_port_url() -> str:
    import socket

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    return f"http://127.0.0.1:{port}/v1"  # nothing listens there once the socket is closed


def test_a_down_server_is_an_error_at_load() -> None:
    url = _closed_port_url()
    start = time.perf_counter()
    with pytest.raises(VlmBenchError, match=f"cannot reach .* at {url}") as info:
        resolve_backend("openai/m", {"base_url": url})
    assert time.perf_counter() - start < 5 and "\n" not in str(info.value)


def test_the_load_check_can_be_turned_off() -> None:
    backend = resolve_backend("openai/m", {"base_url": _closed_port_url(), "check_server": "0"})
    assert backend.name == "openai"


def test_a_server_that_stops_answering_stops_the_run(server: FakeServer) -> None:
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "1", **FAST})
    [ok] = backend.generate([_request("a")], GenerationConfig())
    assert ok.error is None
    server.__exit__()
    with pytest.raises(VlmBenchError, match=r"stopped answering.*re-run to resume"):
        backend.generate([_request("b"), _request("c")], GenerationConfig())


def test_some_failed_requests_are_recorded_not_raised(server: FakeServer) -> None:
    server.fail_first = 1  # 500 on the first call, then answers
    backend = resolve_backend("openai/m", {"base_url": server.url, "retries": "0", **FAST})
    results = backend.generate([_request("a"), _request("b")], GenerationConfig())
    assert sorted(r.error is None for r in results) == [False, True]


def test_constrained_is_refused_where_the_server_ignores_the_schema(server: FakeServer) -> None:
    server.enforces_schema = False  # as transformers serve: "Ignoring unsupported fields"
    backend = resolve_backend("openai/m", {"base_url": server.url})
    config = GenerationConfig(constrained=True)
    with pytest.raises(ConfigError, match="does not enforce response_format") as info:
        backend.generate([_request("a", {"type": "array"})], config)
    assert "\n" not in str(info.value)
    assert len(server.received) == 1  # the probe alone: no episode was sent unconstrained


def test_constrained_is_refused_where_the_server_rejects_the_schema(server: FakeServer) -> None:
    server.fail_first, server.status = 100, 400
    backend = resolve_backend("openai/m", {"base_url": server.url})
    with pytest.raises(ConfigError, match="rejects response_format json_schema"):
        backend.generate([_request("a", {"type": "array"})], GenerationConfig(constrained=True))


def test_constrained_checks_the_server_once(server: FakeServer) -> None:
    backend = resolve_backend("openai/m", {"base_url": server.url})
    config = GenerationConfig(constrained=True)
    for rid in ("a", "b"):
        [result] = backend.generate([_request(rid, {"type": "array"})], config)
        assert result.error is None
    probes = [b for b in server.received if "probe" in json.dumps(b.get("response_format", {}))]
    assert len(probes) == 1


def test_each_concurrent_request_records_its_own_time(server: FakeServer) -> None:
    """Four requests at once, answered after 0.3 s each: each took 0.3 s (not the batch's time
    divided by four, 0.075 s, the same for all); the batch took about 0.3 s too."""
    server.sleep_s = 0.3
    backend = resolve_backend("openai/m", {"base_url": server.url, "concurrency": "4"})
    start = time.perf_counter()
    results = backend.generate([_request(f"r{i}") for i in range(4)], GenerationConfig())
    wall = time.perf_counter() - start
    batch = results[0].batch_latency_s
    assert batch is not None and 0.3 <= batch <= wall
    assert all(0.3 <= r.latency_s <= batch for r in results)
    assert all(r.batch_latency_s == batch for r in results)


def test_settings_beyond_the_openai_api_go_in_the_body(server: FakeServer) -> None:
    backend = resolve_backend("openai/m", {"base_url": server.url})
    backend.generate([_request("a")], GenerationConfig())
    backend.generate([_request("b")], GenerationConfig(repetition_penalty=1.05))
    backend.generate([_request("c")], GenerationConfig(temperature=0.5, top_k=20))
    plain, penalised, sampled = server.received
    assert "repetition_penalty" not in plain and "top_k" not in plain
    assert penalised["repetition_penalty"] == 1.05 and "top_k" not in penalised
    assert sampled["top_k"] == 20


@pytest.mark.parametrize(
    "content_type", ["text/html", "application/json"], ids=["html", "broken-json"]
)
def test_a_200_body_that_is_not_json_is_named_as_such(
    server: FakeServer, content_type: str
) -> None:
    server.raw = (content_type, b"<html><body>502 Bad Gateway from the proxy</body></html>")
    backend = resolve_backend("openai/m", {"base_url": server.url, **FAST})
    (result,) = backend.generate([_request("a")], GenerationConfig())
    assert result.error == (
        "the server sent a body that is not JSON (first 80 bytes: "
        "'<html><body>502 Bad Gateway from the proxy</body></html>')"
    )
