"""docs/scaling.md's Ray recipe on one machine: a head and one worker node, then four runs.

1. ``--ray-address`` the head: its records equal a run with worker processes, field by field.
2. No ``--ray-address`` while the cluster runs (and ``RAY_ADDRESS`` names it): the run starts
   its own local cluster instead of failing.
3. The worker node is killed mid-run: the run ends within ``--exec-stall-s`` with the executions in
   flight written as lost (exit code 3).
4. The node is started again and the same command resumes: its records equal run 1's.

Ray processes are started in a temporary folder of their own (never ``/tmp/ray``) and stopped
by process group at the end; the cluster uses token authentication (``RAY_AUTH_MODE=token``),
as Ray's own ``ray start`` does by default in recent releases. Run it from the repository root:

Usage:
    python benchmarks/ray_two_nodes.py [--port 6391] [--cpus 2] [--stall 20]
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
TASKS = (
    "container_geometry_bowl",
    "slim_object_in_bowl",
    "clear_desk_push_box",
    "cylinder_manipulation",
)
RAY = str(Path(sys.executable).with_name("ray"))


def _ray_start(args: list[str], env: dict[str, str], log: Path) -> subprocess.Popen[bytes]:
    """``ray start ... --block`` in a process group of its own (killed as a whole)."""
    with log.open("ab") as out:
        return subprocess.Popen(
            [RAY, "start", *args, "--block"],
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )


def _stop(proc: subprocess.Popen[bytes], sig: int = signal.SIGTERM) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, sig)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _run(out: Path, env: dict[str, str], *options: str) -> list[str]:
    """The ``vlm-bench run`` argv for ``TASKS`` into ``out``."""
    args = [sys.executable, "-c", "from vlm_bench.cli.main import main; main()"]
    args += ["run", "--model", "oracle"]
    for task in TASKS:
        args += ["--task", task]
    args += ["--seeds", "0", "--resolution", "32", "--batch-size", "1", "--no-progress"]
    return [*args, "--out", str(out), *options]


def _records(run_dir: Path) -> dict[str, Any]:
    rows: dict[str, Any] = {}
    for line in (run_dir / "records.jsonl").read_text().splitlines():
        rec = json.loads(line)
        for name in ("latency_s", "batch_latency_s", "created", "cached"):
            rec.pop(name, None)
        if rec.get("execution"):
            rec["execution"].pop("wall_time_s", None)
        rows[rec["key"]] = rec  # the latest record of each episode
    return rows


def _wait_lines(path: Path, n: int, proc: subprocess.Popen[bytes], timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        if path.exists() and path.read_bytes().count(b"\n") >= n:
            return
        time.sleep(0.2)
    raise SystemExit(f"no {n} records in {path} (run ended: {proc.poll()})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=6391, help="the head's GCS port")
    parser.add_argument("--cpus", type=int, default=2, help="CPUs of the worker node")
    parser.add_argument("--stall", type=float, default=20.0, help="--exec-stall-s of run 3")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="vlm-bench-ray-"))
    ip = socket.gethostbyname(socket.gethostname())
    address = f"{ip}:{args.port}"
    env = {k: v for k, v in os.environ.items() if k != "RAY_ADDRESS"}
    env.update(RAY_AUTH_MODE="token", MUJOCO_GL="egl", PYTHONPATH=str(ROOT))
    common = ["--temp-dir", str(work / "ray")]
    log = work / "ray.log"
    head = _ray_start(["--head", "--port", str(args.port), "--num-cpus", "0", *common], env, log)
    time.sleep(15)
    node = _ray_start(["--address", address, "--num-cpus", str(args.cpus), *common], env, log)
    time.sleep(15)
    ok = True
    try:
        ray = ["--exec-backend", "ray", "--exec-workers", str(args.cpus)]
        process = subprocess.run(_run(work / "process" / "run", env), env=env, cwd=ROOT)
        first = subprocess.run(
            _run(work / "ray" / "run", env, *ray, "--ray-address", address), env=env, cwd=ROOT
        )
        same = _records(work / "ray" / "run") == _records(work / "process" / "run")
        print(f"1. --ray-address: exit {first.returncode}; records equal a process run: {same}")
        ok &= first.returncode == 0 and process.returncode == 0 and same

        local = subprocess.run(
            _run(work / "local" / "run", env, *ray), env={**env, "RAY_ADDRESS": address}, cwd=ROOT
        )
        print(f"2. no --ray-address beside a running cluster: exit {local.returncode}")
        ok &= local.returncode == 0

        killed_dir = work / "killed" / "run"
        command = _run(
            killed_dir, env, *ray, "--ray-address", address, "--exec-stall-s", str(args.stall)
        )
        proc = subprocess.Popen(command, env=env, cwd=ROOT)
        _wait_lines(killed_dir / "records.jsonl", 1, proc, timeout=300)
        _stop(node, signal.SIGKILL)
        killed_at = time.monotonic()
        code = proc.wait(timeout=args.stall + 300)
        took = time.monotonic() - killed_at
        lost = [r for r in _records(killed_dir).values() if r["status"] == "error"]
        print(
            f"3. worker node killed: exit {code} after {took:.0f} s, {len(lost)} execution(s) lost"
        )
        ok &= code == 3 and bool(lost) and took < args.stall + 120

        node = _ray_start(["--address", address, "--num-cpus", str(args.cpus), *common], env, log)
        time.sleep(15)
        resumed = subprocess.run(command, env=env, cwd=ROOT)
        equal = _records(killed_dir) == _records(work / "ray" / "run")  # both run ids: "run"
        print(f"4. node back, resumed: exit {resumed.returncode}; records equal run 1: {equal}")
        ok &= resumed.returncode == 0 and equal
    finally:
        _stop(node)
        _stop(head)
    print("all as documented" if ok else f"FAILED (logs under {work})")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
