"""The ``vlm-bench`` command line: a thin layer over the Python API.

Listing commands and ``--help`` import neither torch nor mujoco; heavy imports live inside the
commands. User errors (:class:`VlmBenchError`) and usage errors (a bad option value, an unknown
option or command) print one line, no traceback, exit code 2.
"""

from __future__ import annotations

import errno
import sys
from typing import NoReturn

import typer
import typer.main
from typer.exceptions import TyperException

from vlm_bench.cli.exit_codes import EXIT_CODES_HELP, ExitCode
from vlm_bench.errors import VlmBenchError

app = typer.Typer(
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    help="Evaluate vision-language models as planners for aerial manipulation.",
    epilog=EXIT_CODES_HELP,
    context_settings={"auto_envvar_prefix": "VLM_BENCH"},
)


def _register() -> None:
    if app.registered_commands:  # once per process (tests call main() repeatedly)
        return
    from vlm_bench.cli import models_cmd, report_cmd, world_cmds

    world_cmds.register(app)
    report_cmd.register(app)
    models_cmd.register(app)
    try:
        from vlm_bench.cli import execute_cmd, export_cmds, prompt_cmd, run_cmds
    except ImportError:  # the planning pipeline commands are optional during development
        return
    run_cmds.register(app)
    prompt_cmd.register(app)
    execute_cmd.register(app)
    export_cmds.register(app)
    from vlm_bench.cli import export_demos_cmd, export_sft_cmd

    export_sft_cmd.add_to(export_cmds.export_app)
    export_demos_cmd.add_to(export_cmds.export_app)


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _usage_error(exc: TyperException) -> str:
    """A usage error (bad option value, unknown option or command) as one line; empty when
    click already printed what to do (the help, for a bare ``vlm-bench``)."""
    format_message = getattr(exc, "format_message", None)
    message = format_message() if callable(format_message) else str(exc)
    if not message.strip():
        return ""
    ctx = getattr(exc, "ctx", None)
    where = getattr(ctx, "command_path", "") or "vlm-bench"
    return _one_line(f"{where}: {message} (see {where} --help)")


def main(argv: list[str] | None = None) -> None:
    """Console entry point: run the app; user errors and usage errors print one line on stderr.

    Exit codes: :class:`~vlm_bench.cli.exit_codes.ExitCode`.
    """
    _register()
    try:
        result = typer.main.get_command(app).main(
            args=argv, prog_name="vlm-bench", standalone_mode=False
        )
    except VlmBenchError as exc:
        _fail(_one_line(str(exc)), ExitCode.USAGE)
    except TyperException as exc:
        code = int(getattr(exc, "exit_code", 2))
        line = _usage_error(exc)
        if not line:
            sys.exit(code)
        _fail(line, code)
    except typer.Abort:
        _fail("aborted", ExitCode.FAILED)
    except OSError as exc:  # a file or folder the user named cannot be read or written
        if exc.errno == errno.EPIPE:  # output piped into a reader that quit
            sys.exit(1)
        name = f": {exc.filename}" if exc.filename else ""
        _fail(_one_line(f"{exc.strerror or exc}{name}"), ExitCode.FAILED)
    sys.exit(result if isinstance(result, int) else 0)


def _fail(message: str, code: int) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    sys.exit(code)
