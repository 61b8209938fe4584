"""A backend of another package, end to end: ``tests/backends/plugin_package`` is an installed
distribution (one module and its ``dist-info`` with a ``vlm_bench.backends`` entry point) put on
``PYTHONPATH``, so :mod:`importlib.metadata` finds it as it would any installed package, and
``vlm-bench run --model tinyplan/<model>`` runs through it against a server on 127.0.0.1. Its
module is all a new HTTP backend writes (docs/design.md#how-to-add): the request backend's
retries, backoff and concurrency come with the base class."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

PACKAGE = Path(__file__).parent / "plugin_package"
TASK = "standard_pick_place"
PLAN = [
    {"subtask": 0, "tasktype": "UAV", "direction": "front"},
    {"subtask": 1, "tasktype": "ARM", "object": "gray_cube", "skill": "pick"},
]
PINNED = "Server is pinned to m; requested 'wrongname'"


class PlanServer:
    """Answers ``POST /plan`` with :data:`PLAN` for model ``m``, 400 for any other model."""

    def __init__(self) -> None:
        self.bodies: list[dict[str, str]] = []
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:
                pass

            def do_POST(self) -> None:
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                server.bodies.append(body)
                ok = body["model"] == "m"
                data = json.dumps({"plan": PLAN} if ok else {"detail": PINNED}).encode()
                self.send_response(200 if ok else 400)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(data)))
                self.end_headers()
                self.wfile.write(data)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}"


@pytest.fixture
def server() -> Iterator[PlanServer]:
    fake = PlanServer()
    thread = threading.Thread(target=fake.httpd.serve_forever, daemon=True)
    thread.start()
    yield fake
    fake.httpd.shutdown()
    fake.httpd.server_close()


def _run(out: Path, model: str, url: str) -> subprocess.CompletedProcess[str]:
    paths = [str(PACKAGE), os.environ.get("PYTHONPATH", "")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p)}
    code = "import sys; from vlm_bench.cli.main import main; main(sys.argv[1:])"
    return subprocess.run(
        [sys.executable, "-c", code, "run", "--model", model, "--task", TASK, "--seeds", "0",
         "--instruction", "explicit", "--no-execute", "--no-progress", "--out", str(out),
         "-M", f"base_url={url}", "-M", "backoff_s=0.01"],
        env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def test_an_entry_point_backend_runs_end_to_end(server: PlanServer, tmp_path: Path) -> None:
    done = _run(tmp_path / "run", "tinyplan/m", server.url)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    records = [json.loads(line) for line in (tmp_path / "run" / "records.jsonl").open()]
    assert len(records) == 1 and records[0]["model"] == "tinyplan/m"
    assert json.loads(records[0]["raw_output"]) == PLAN
    assert records[0]["scores"]["s_obj"] > 0  # parsed and scored against the GT
    manifest = json.loads((tmp_path / "run" / "manifest.json").read_text())
    assert manifest["backend"] == "tinyplan"
    assert len(server.bodies) == 1 and "gray_cube" in server.bodies[0]["prompt"]


def test_a_client_error_keeps_the_servers_reason_and_is_not_retried(
    server: PlanServer, tmp_path: Path
) -> None:
    done = _run(tmp_path / "run", "tinyplan/wrongname", server.url)
    assert done.returncode == 3, done.stdout[-2000:] + done.stderr[-2000:]
    assert PINNED in done.stdout + done.stderr
    record = json.loads((tmp_path / "run" / "records.jsonl").read_text().splitlines()[0])
    assert record["backend_error"] == f"HTTP 400: {json.dumps({'detail': PINNED})}"
    assert len(server.bodies) == 1  # a 400 is final: asking again gets the same answer
