"""Executes on a Ray cluster (``--exec-backend ray``; needs the ``ray`` extra).

Each execution is a Ray task of one CPU: Ray schedules the tasks over the cluster's nodes and
retries a task whose worker process died (:data:`MAX_RETRIES`). With no address, a local
cluster of ``workers`` CPUs is started for the run and stopped after it, even where another
cluster runs on the machine (``address="local"``); with one (``--ray-address auto`` or
``head:6379``, the run on a node of the cluster), the run joins that cluster, whose nodes need
vlm-bench installed (see the two-machine recipe in docs/scaling.md). Ray Client addresses
(``ray://``) are refused: they need ``ray[client]`` and a matching server.

What a user meets is vlm-bench's, not Ray's: an address where nothing answers is refused before
the run folder is written (:func:`check_ray_address` tries a TCP connection for
:data:`PROBE_S` seconds: Ray itself retries for minutes); Ray's ``ray.init`` replaces the
process's SIGINT/SIGTERM handlers, which are put back, so Ctrl-C and SIGTERM stop a Ray run as
any other (exit 130/143, resumable); and a node of the cluster that dies is announced on stderr
within a minute (:class:`NodeWatch`).
"""

from __future__ import annotations

import logging
import signal
import socket
import sys
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import contextmanager
from typing import Any, TypeVar

from vlm_bench.errors import ConfigError
from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job

J = TypeVar("J")
R = TypeVar("R")

MAX_RETRIES = 2
"""Times Ray runs an execution again after its worker process died."""
PROBE_S = 5.0
"""How long :func:`check_ray_address` waits for the head to accept a connection (s)."""
WATCH_S = 10.0
"""How often :class:`NodeWatch` looks at the cluster's nodes (s). Ray marks a node dead after
about 15 s of failed health checks, so a lost node is announced well within a minute."""


def _host_port(address: str) -> tuple[str, int] | None:
    host, sep, port = address.rpartition(":")
    if not sep or not host or not port.isdigit():
        return None
    return host.strip("[]"), int(port)


def check_ray_address(address: str | None) -> None:
    """Refuse addresses the run cannot join (before anything is written).

    Raises:
        ConfigError: A Ray Client address (``ray://``), or a ``host:port`` where nothing
            accepts a connection within :data:`PROBE_S` seconds.
    """
    if address is not None and address.startswith("ray://"):
        raise ConfigError(
            f"--ray-address {address}: Ray Client addresses are not supported; run vlm-bench "
            "on a node of the cluster with --ray-address auto (or the head's host:6379)"
        )
    where = _host_port(address) if address not in (None, "auto", "local") else None
    if where is None:
        return
    try:
        with socket.create_connection(where, timeout=PROBE_S):
            pass
    except OSError as exc:
        why = "timed out" if isinstance(exc, TimeoutError) else (exc.strerror or str(exc))
        raise ConfigError(
            f"--ray-address {address}: no Ray head answers there ({why}); start one with "
            "`ray start --head --port 6379` or give the head's host:port"
        ) from None


@contextmanager
def _own_signal_handlers() -> Iterator[None]:
    """Keep this process's SIGINT/SIGTERM handlers across ``ray.init`` (which installs its own:
    a SIGTERM would then exit 15 with a native stack dump instead of stopping the run)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    kept = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for signum, handler in kept.items():
            if handler is not None:
                signal.signal(signum, handler)


class NodeWatch:
    """Announces, once each, the cluster's nodes that die while the run uses them.

    Args:
        nodes: Returns the cluster's nodes as Ray's ``ray.nodes()`` does (dicts with
            ``NodeID``, ``Alive`` and ``NodeManagerAddress``).
        warn: Prints one line.
        in_flight: The executions in flight (named in the warning).
        stall_s: When the executions in flight are given up (named in the warning).
    """

    def __init__(
        self,
        nodes: Callable[[], list[dict[str, Any]]],
        warn: Callable[[str], None],
        in_flight: Callable[[], int],
        stall_s: float,
    ) -> None:
        self._nodes = nodes
        self._warn = warn
        self._in_flight = in_flight
        self._stall_s = stall_s
        self._seen: set[str] = set()
        self._lost: set[str] = set()
        self._stop = threading.Event()

    def check(self) -> None:
        """Look once: warn about every node seen alive before that is dead or gone now."""
        try:
            nodes = self._nodes()
        except Exception:  # noqa: BLE001  (a watcher must never end the run)
            return
        alive = {str(n.get("NodeID")): n for n in nodes if n.get("Alive")}
        named = {str(n.get("NodeID")): n for n in nodes}
        for node in sorted(self._seen - set(alive) - self._lost):
            self._lost.add(node)
            where = named.get(node, {}).get("NodeManagerAddress") or node[:12]
            self._warn(
                f"warning: Ray node {where} is gone ({len(alive)} node(s) left, "
                f"{self._in_flight()} execution(s) in flight): Ray runs its executions again "
                f"on the other nodes; those still unfinished after {self._stall_s:g} s are "
                "written as lost and a resume runs them (--exec-stall-s)"
            )
        self._seen |= set(alive)

    def start(self) -> None:
        """Check every :data:`WATCH_S` seconds in a daemon thread until :meth:`stop`."""

        def loop() -> None:
            while not self._stop.wait(WATCH_S):
                self.check()

        self.check()
        threading.Thread(target=loop, name="ray-node-watch", daemon=True).start()

    def stop(self) -> None:
        """End the checks."""
        self._stop.set()


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


class RayPool:
    """Sends executions to Ray as tasks (the cluster is joined on the first execution).

    Args:
        workers: CPUs of the local cluster started when ``address`` is None (on a cluster:
            only what the progress display counts as running).
        address: The cluster's address; None = start a local one.
    """

    def __init__(
        self, workers: int, address: str | None = None, stall_s: float | None = None
    ) -> None:
        from vlm_bench.types.execution import ExecutionOptions

        self.workers = workers
        self.address = address
        self.stall_s = ExecutionOptions().stall_s if stall_s is None else stall_s
        self._watch: NodeWatch | None = None
        self._ray: Any = None
        self._task: Any = None
        self._started = False
        self._tasks: dict[Callable[..., Any], Any] = {}
        self._refs: dict[int, Any] = {}
        """The object refs of executions in flight (for cancelling; finished ones are dropped so
        a long sweep does not pin its results in the object store)."""

    def _connect(self) -> Any:
        if self._ray is not None:
            return self._ray
        try:
            import ray
        except ImportError as exc:
            raise ConfigError("--exec-backend ray needs Ray: pip install -e '.[ray]'") from exc
        if not ray.is_initialized():
            check_ray_address(self.address)
            env = {"env_vars": {"MUJOCO_GL": "egl"}}
            try:
                with _own_signal_handlers():
                    if self.address is None:
                        ray.init(
                            address="local",
                            num_cpus=self.workers,
                            runtime_env=env,
                            include_dashboard=False,
                            logging_level=logging.WARNING,  # not Ray's start-up chatter
                        )
                        self._started = True
                    else:
                        ray.init(address=self.address, runtime_env=env)
            except (ConnectionError, ValueError, RuntimeError) as exc:
                where = self.address or "a local cluster"
                first = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
                raise ConfigError(f"cannot start Ray on {where}: {first[:300]}") from None
        self._task = ray.remote(num_cpus=1, max_retries=MAX_RETRIES)(execute_job)
        self._ray = ray
        if not self._started:  # a cluster of other machines: watch its nodes
            self._watch = NodeWatch(ray.nodes, _stderr, lambda: self.held, self.stall_s)
            self._watch.start()
        return ray

    def submit(self, job: ExecutionJob) -> Future[Executed]:
        self._connect()
        return self._track(self._task.remote(job))

    def submit_call(self, fn: Callable[[J], R], job: J) -> Future[R]:
        ray = self._connect()
        task = self._tasks.get(fn)
        if task is None:
            task = self._tasks[fn] = ray.remote(num_cpus=1, max_retries=MAX_RETRIES)(fn)
        return self._track(task.remote(job))

    def _track(self, ref: Any) -> Future[Any]:
        future: Future[Any] = ref.future()
        self._refs[id(future)] = ref
        future.add_done_callback(lambda done: self._refs.pop(id(done), None))
        return future

    @property
    def held(self) -> int:
        """Object refs held: executions in flight (a finished one's ref is dropped)."""
        return len(self._refs)

    def restart(self) -> None:
        return None  # Ray restarts dead workers itself

    def abandon(self) -> None:
        ray = self._ray
        if ray is not None:
            for ref in list(self._refs.values()):
                ray.cancel(ref, force=True)
        self._refs.clear()

    def close(self, cancel: bool = False) -> None:
        ray = self._ray
        if ray is None:
            return
        if cancel:
            for ref in list(self._refs.values()):
                ray.cancel(ref, force=True)
        self._refs.clear()
        if self._watch is not None:
            self._watch.stop()
            self._watch = None
        if self._started:
            ray.shutdown()
        self._ray = None
