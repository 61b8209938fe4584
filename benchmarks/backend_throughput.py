"""Backend throughput: episodes/s against batch size (hf) and against concurrency (openai).

hf: a tiny random-weight LLaVA (benchmarks/tiny_vlms.py) answers the same requests (the real
system prompt, four labelled 448 px views) at each batch size, all in one process, so the ratios
to batch 1 come from one run on one machine. openai: the same requests through the openai
backend at each concurrency, against a local fake OpenAI server that answers after a fixed
delay (the client's concurrency alone), and against ``transformers serve`` on 127.0.0.1 serving
that tiny LLaVA when FastAPI and Uvicorn import (``--serve-path`` adds a folder holding them to
the server's PYTHONPATH).

    MUJOCO_GL=egl python benchmarks/backend_throughput.py [--requests 16] [--serve-path DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import tiny_vlms
from _machine import machine

from vlm_bench.backends.hf import HfBackend
from vlm_bench.episodes import make_episode
from vlm_bench.prompting import build_prompt
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.run import RunConfig


def _system_prompt() -> str:
    episode = make_episode("standard_pick_place", 0)
    prompt_config = RunConfig(model="mock", images=False).prompt_config("explicit")
    return build_prompt(episode, {}, prompt_config).to_request("x").system


REPEATS = 2
"""Each figure is the best of this many passes (the machine is shared; the best pass is the one
least slowed by others)."""


def _rate(run: Any, n: int) -> tuple[float, float]:
    seconds = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        run()
        seconds.append(time.perf_counter() - start)
    return n / min(seconds), min(seconds)


def hf_sweep(
    folder: Path, requests: list[Any], sizes: list[int], tokens: int
) -> list[dict[str, Any]]:
    """Episodes/s of the hf backend at each batch size (one warm-up batch first)."""
    from vlm_bench.backends import resolve_backend

    backend = resolve_backend(str(folder), {})
    assert isinstance(backend, HfBackend)
    backend.generate(requests[:2], GenerationConfig(max_new_tokens=tokens, batch_size=2))
    rows = []
    for size in sizes:
        config = GenerationConfig(max_new_tokens=tokens, batch_size=size)
        rate, seconds = _rate(lambda c=config: backend.generate(requests, c), len(requests))
        rows.append({"batch_size": size, "episodes_per_s": rate, "seconds": seconds})
    return rows


class _FixedDelayServer:
    """An OpenAI-compatible chat endpoint that answers every request after ``delay_s``."""

    def __init__(self, delay_s: float) -> None:
        delay = delay_s

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:
                pass

            def _send(self, payload: dict[str, Any]) -> None:
                data = json.dumps(payload).encode()
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(data)))
                self.end_headers()
                self.wfile.write(data)

            def do_GET(self) -> None:
                self._send({"object": "list", "data": []})

            def do_POST(self) -> None:
                self.rfile.read(int(self.headers["Content-Length"]))
                time.sleep(delay)
                message = {"role": "assistant", "content": "[]"}
                choice = {"index": 0, "finish_reason": "stop", "message": message}
                self._send(
                    {
                        "id": "x",
                        "object": "chat.completion",
                        "created": 0,
                        "model": "m",
                        "choices": [choice],
                    }
                )

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"
        threading.Thread(target=self.httpd.serve_forever, daemon=True).start()

    def close(self) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _start_transformers_serve(folder: Path, serve_path: str | None) -> tuple[Any, str] | None:
    """``transformers serve <folder>`` on a free loopback port, or None if it cannot start."""
    env = dict(os.environ, HF_HUB_OFFLINE="1")
    if serve_path:
        env["PYTHONPATH"] = os.pathsep.join(p for p in (serve_path, env.get("PYTHONPATH")) if p)
    port = _free_port()
    exe = Path(sys.executable).with_name("transformers")
    proc = subprocess.Popen(
        [str(exe), "serve", str(folder), "--host", "127.0.0.1", "--port", str(port)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    url = f"http://127.0.0.1:{port}/v1"
    for _ in range(120):
        if proc.poll() is not None:
            return None
        try:
            with urllib.request.urlopen(f"{url}/models", timeout=1):
                return proc, url
        except OSError:
            time.sleep(0.5)
    proc.terminate()
    return None


def openai_sweep(
    model: str, url: str, requests: list[Any], levels: list[int], tokens: int
) -> list[dict[str, Any]]:
    """Episodes/s of the openai backend at each concurrency (one warm-up request first)."""
    from vlm_bench.backends import resolve_backend

    rows = []
    for level in levels:
        backend = resolve_backend(f"openai/{model}", {"base_url": url, "concurrency": str(level)})
        backend.generate(requests[:1], GenerationConfig(max_new_tokens=tokens))
        rate, seconds = _rate(
            lambda b=backend: b.generate(requests, GenerationConfig(max_new_tokens=tokens)),
            len(requests),
        )
        rows.append({"concurrency": level, "episodes_per_s": rate, "seconds": seconds})
        backend.close()
    return rows


def _print(title: str, key: str, rows: list[dict[str, Any]]) -> None:
    print(title)
    base = rows[0]["episodes_per_s"]
    for row in rows:
        ratio = row["episodes_per_s"] / base
        print(f"  {key} {row[key]:>3}: {row['episodes_per_s']:7.2f} episodes/s  x{ratio:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=16, help="Requests per measurement.")
    parser.add_argument("--tokens", type=int, default=16, help="max_new_tokens.")
    parser.add_argument("--serve-path", help="Folder with FastAPI/Uvicorn for the server.")
    parser.add_argument("--delay", type=float, default=0.1, help="Fake server's delay (s).")
    parser.add_argument("--out", type=Path, help="Write the figures as JSON here.")
    args = parser.parse_args()
    system = _system_prompt()
    corpus = [system, *tiny_vlms.VIEWS.values()] * 3
    requests = tiny_vlms.four_view_requests(system, args.requests, size=448)
    result: dict[str, Any] = {"machine": machine(), "requests": args.requests}
    with tempfile.TemporaryDirectory() as tmp:
        folder = tiny_vlms.ARCHS[0].build(corpus).save(Path(tmp) / "tiny-llava")
        result["hf"] = hf_sweep(folder, requests, [1, 2, 4, 8, 16], args.tokens)
        levels = [1, 2, 4, 8, 16]
        fake = _FixedDelayServer(args.delay)
        try:
            # 4x the requests: a pass at 100 ms a request is short enough for noise to swamp it
            many = tiny_vlms.four_view_requests(system, 4 * args.requests, size=448)
            result["openai_fake"] = openai_sweep("m", fake.url, many, levels, args.tokens)
        finally:
            fake.close()
        started = _start_transformers_serve(folder, args.serve_path)
        if started is not None:
            proc, url = started
            try:
                result["openai_serve"] = openai_sweep(
                    str(folder), url, requests, levels, args.tokens
                )
            finally:
                os.killpg(proc.pid, 15)
                proc.wait(timeout=30)
    print(f"machine: {result['machine']}; best of {REPEATS} passes, {args.requests} requests")
    _print("hf (tiny LLaVA), episodes/s by batch size:", "batch_size", result["hf"])
    fake_title = (
        f"openai, fake server answering after {args.delay * 1000:.0f} ms "
        f"({4 * args.requests} requests), by concurrency:"
    )
    _print(fake_title, "concurrency", result["openai_fake"])
    if "openai_serve" in result:
        serve_title = "openai, transformers serve (tiny LLaVA, loopback), by concurrency:"
        _print(serve_title, "concurrency", result["openai_serve"])
    else:
        print("transformers serve did not start (needs FastAPI and Uvicorn: --serve-path)")
    if args.out:
        args.out.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
