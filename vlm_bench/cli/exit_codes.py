"""The exit codes of ``vlm-bench``: the one list that ``--help``, the README and the code share."""

from __future__ import annotations

from enum import IntEnum


class ExitCode(IntEnum):
    """What a script or CI can tell from the exit status of a command."""

    OK = 0
    """Done (a run: every episode has an answer)."""
    FAILED = 1
    """Failed or aborted (e.g. a file that cannot be written)."""
    USAGE = 2
    """A user or usage error, printed as one line on stderr."""
    UNANSWERED = 3
    """``run`` finished, but some episodes have no result (backend errors after retries, or
    executions lost to the infrastructure): re-run the same command to retry them."""
    INTERRUPTED = 130
    """Stopped by Ctrl-C (SIGINT): finished episodes are saved; re-run to resume."""
    TERMINATED = 143
    """Stopped by SIGTERM, as Ctrl-C."""


EXIT_CODES_HELP = (
    "Exit codes: 0 done; 1 failed or aborted; 2 user or usage error; 3 run finished with "
    "episodes without a result (backend errors after retries, lost executions; re-run to retry); "
    "130 interrupted (Ctrl-C); 143 terminated (SIGTERM)."
)
"""The codes in one line, for ``--help``."""
