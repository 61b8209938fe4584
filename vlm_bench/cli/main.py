"""The ``vlm-bench`` command line: a thin layer over the Python API.

Listing commands and ``--help`` import neither torch nor mujoco; heavy imports live inside the
commands. User errors (:class:`VlmBenchError`) print one line, no traceback, exit code 2.
"""

from __future__ import annotations

import sys

import typer

from vlm_bench.errors import VlmBenchError

app = typer.Typer(
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    help="Evaluate vision-language models as planners for aerial manipulation.",
    context_settings={"auto_envvar_prefix": "VLM_BENCH"},
)


def _register() -> None:
    from vlm_bench.cli import models_cmd, report_cmd, world_cmds

    world_cmds.register(app)
    models_cmd.register(app)
    report_cmd.register(app)
    try:
        from vlm_bench.cli import execute_cmd, run_cmds
    except ImportError:  # the planning pipeline commands are optional during development
        return
    run_cmds.register(app)
    execute_cmd.register(app)


def main() -> None:
    """Console entry point: run the app, printing user errors as one line."""
    _register()
    try:
        app()
    except VlmBenchError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
