"""Executes on a Ray cluster (``--exec-backend ray``; needs the ``ray`` extra).

Each execution is a Ray task of one CPU: Ray schedules the tasks over the cluster's nodes and
retries a task whose worker process died (:data:`MAX_RETRIES`). With no address, a local
cluster of ``workers`` CPUs is started for the run and stopped after it, even where another
cluster runs on the machine (``address="local"``); with one (``--ray-address auto`` or
``head:6379``, the run on a node of the cluster), the run joins that cluster, whose nodes need
vlm-bench installed (see the two-machine recipe in docs/scaling.md). Ray Client addresses
(``ray://``) are refused: they need ``ray[client]`` and a matching server.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

from vlm_bench.errors import ConfigError
from vlm_bench.runner.execution_jobs import Executed, ExecutionJob, execute_job
from vlm_bench.runner.execution_pools import J, R

MAX_RETRIES = 2
"""Times Ray runs an execution again after its worker process died."""


def check_ray_address(address: str | None) -> None:
    """Refuse addresses the run cannot join (before anything is written).

    Raises:
        ConfigError: A Ray Client address (``ray://``).
    """
    if address is not None and address.startswith("ray://"):
        raise ConfigError(
            f"--ray-address {address}: Ray Client addresses are not supported; run vlm-bench "
            "on a node of the cluster with --ray-address auto (or the head's host:6379)"
        )


class RayPool:
    """Sends executions to Ray as tasks (the cluster is joined on the first execution).

    Args:
        workers: CPUs of the local cluster started when ``address`` is None (on a cluster:
            only what the progress display counts as running).
        address: The cluster's address; None = start a local one.
    """

    def __init__(self, workers: int, address: str | None = None) -> None:
        self.workers = workers
        self.address = address
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
                if self.address is None:
                    ray.init(
                        address="local",
                        num_cpus=self.workers,
                        runtime_env=env,
                        include_dashboard=False,
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
        if self._started:
            ray.shutdown()
        self._ray = None
