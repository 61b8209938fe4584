"""Where a run's plans are executed: the ``--exec-*`` and ``--ray-address`` options of ``run``
and ``rescore``, checked before anything is written."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Literal

import typer

from vlm_bench.cli.options import finite
from vlm_bench.errors import ConfigError

if TYPE_CHECKING:
    from vlm_bench.types.execution import ExecutionOptions

ExecWorkers = Annotated[
    int | None,
    typer.Option(
        min=0,
        help="Plans executed at once (default: the machine's cores; 0 = one by one in this "
        "process).",
    ),
]
ExecBackend = Annotated[
    str, typer.Option(help="Where plans are executed: process (this machine) or ray.")
]
RayAddress = Annotated[
    str | None,
    typer.Option(help="Ray cluster to execute on (--exec-backend ray; default: a local one)."),
]
ExecStall = Annotated[
    float | None,
    typer.Option(
        min=0.001,
        help="Give up the executions in flight when none finishes for this long (s; default 600): "
        "a hung worker or a lost node; a resume runs them again.",
    ),
]


def execution_options(
    workers: int | None, backend: str, address: str | None, stall_s: float | None = None
) -> ExecutionOptions:
    """``--exec-workers/--exec-backend/--ray-address/--exec-stall-s`` checked (before anything
    is written)."""
    import importlib.util

    from vlm_bench.types.execution import ExecutionOptions

    if backend not in ("process", "ray"):
        raise ConfigError(f"unknown --exec-backend {backend!r}; use process or ray")
    if address is not None and backend != "ray":
        raise ConfigError("--ray-address needs --exec-backend ray")
    if backend == "ray" and importlib.util.find_spec("ray") is None:
        raise ConfigError("--exec-backend ray needs Ray: pip install -e '.[ray]'")
    if backend == "ray":
        from vlm_bench.runner.executions_ray import check_ray_address

        check_ray_address(address)
    kind: Literal["process", "ray"] = "ray" if backend == "ray" else "process"
    options = ExecutionOptions(workers=workers, backend=kind, ray_address=address)
    if stall_s is None:
        return options
    return options.model_copy(update={"stall_s": finite("--exec-stall-s", stall_s)})
