"""Ray runs that never hang: a head that does not answer is refused in seconds with one line and
nothing written; SIGTERM stops a Ray run with 143 and the resume line; a lost node is announced."""

from __future__ import annotations

import signal
import socket
import subprocess
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from vlm_bench.storage import latest_records

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
TASKS = ("container_geometry_bowl", "slim_object_in_bowl", "clear_desk_push_box")
"""Tasks whose GT executions take about 2 s."""

pytestmark = pytest.mark.skipif(
    __import__("importlib").util.find_spec("ray") is None, reason="the ray extra is not installed"
)


def _closed_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])  # closed again when the block ends


def test_an_address_where_nothing_answers_fails_fast_with_one_line(
    cli: Cli, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    address = f"127.0.0.1:{_closed_port()}"
    args = cli.run_args(out, "oracle", TASKS[:1], "0", "--resolution", "32")
    start = time.monotonic()
    done = cli.run(*args, "--exec-backend", "ray", "--ray-address", address, timeout=60)
    assert time.monotonic() - start < 30
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: --ray-address"), done.stderr
    assert address in lines[0] and "ray start --head" in lines[0]
    assert not out.exists()  # nothing written


@pytest.mark.slow  # starts a local Ray cluster: about a minute on a 2-core machine
def test_sigterm_stops_a_ray_run_with_143_and_it_resumes(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    options = ("--resolution", "32", "--batch-size", "1", "--exec-workers", "2")
    args = cli.run_args(out, "oracle", TASKS, "0-1", *options)
    proc = subprocess.Popen(
        cli.command(*args, "--exec-backend", "ray"),
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    records = out / "records.jsonl"
    cli.wait_for_records(proc, records, 1, timeout=180)  # Ray runs the executions now
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 143, stderr
    assert "terminated" in stderr and "re-run the same command to resume" in stderr
    assert "Traceback" not in stderr and "Stack trace" not in stderr
    resumed = cli.run(*args, timeout=300)  # worker processes this time: the same records
    assert resumed.returncode == 0, resumed.stderr
    assert len(latest_records(records)) == len(TASKS) * 2 * 2


def _node(node_id: str, alive: bool) -> dict[str, Any]:
    return {"NodeID": node_id, "Alive": alive, "NodeManagerAddress": f"10.0.0.{node_id}"}


def test_a_lost_node_is_announced_once() -> None:
    from vlm_bench.runner.executions_ray import NodeWatch

    views = [
        [_node("1", True), _node("2", True)],
        [_node("1", True), _node("2", False)],  # Ray marked node 2 dead
        [_node("1", True)],  # and forgot it
        [_node("1", True), _node("3", True)],  # a new node joins: nothing to say
    ]
    said: list[str] = []
    watch = NodeWatch(lambda: views.pop(0), said.append, lambda: 4, 600.0)
    for _ in range(4):
        watch.check()
    assert len(said) == 1
    assert "10.0.0.2 is gone" in said[0] and "4 execution(s) in flight" in said[0]
    assert "600 s" in said[0] and "resume" in said[0]


def test_a_failing_node_listing_never_ends_the_run() -> None:
    from vlm_bench.runner.executions_ray import NodeWatch

    def broken() -> list[dict[str, Any]]:
        raise ConnectionError("GCS unreachable")

    said: list[str] = []
    NodeWatch(broken, said.append, lambda: 0, 600.0).check()
    assert said == []
