"""User and configuration errors.

Model output never raises: it is data (see ``vlm_bench.parsing``). Exceptions are reserved for
mistakes a user can fix, all rooted at :class:`VlmBenchError`, whose message is one line that names
what is wrong and, where there is a closed set, the valid options. The CLI prints that line alone.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from pydantic import ValidationError


class VlmBenchError(Exception):
    """Root of every error vlm-bench raises on purpose."""


def _options(valid: Iterable[str], limit: int = 12) -> str:
    items = sorted(valid)
    shown = ", ".join(items[:limit])
    more = f", ... ({len(items) - limit} more)" if len(items) > limit else ""
    return f"{shown}{more}"


class UnknownNameError(VlmBenchError):
    """A name (task, object kind, colour, backend, ...) that is not registered."""

    def __init__(self, what: str, name: str, valid: Iterable[str]) -> None:
        self.what, self.name = what, name
        self.valid = sorted(valid)
        super().__init__(f"unknown {what} {name!r}; valid: {_options(self.valid)}")


class DuplicateNameError(VlmBenchError):
    """A registry entry registered twice."""

    def __init__(self, what: str, name: str) -> None:
        super().__init__(f"duplicate {what} {name!r}: names must be unique")


class DataFileError(VlmBenchError):
    """A shipped or user-supplied data file that fails validation: names the file and the field."""

    def __init__(self, path: str, detail: str) -> None:
        self.path = path
        super().__init__(f"{path}: {detail}")


class ConfigError(VlmBenchError):
    """An invalid option or combination of options."""


class MissingExtraError(VlmBenchError):
    """An optional dependency is needed for the requested feature."""

    def __init__(self, package: str, extra: str) -> None:
        super().__init__(
            f"{package} is not installed; install it with: pip install 'vlm-bench[{extra}]'"
        )


class EpisodeGenerationError(VlmBenchError):
    """No valid layout could be sampled for a task and seed."""


class Problem(NamedTuple):
    """The first problem of a pydantic ``ValidationError``, for a one-line message."""

    where: str
    """Field path (``views[1]``, ``generation.temperature``); empty for the whole object."""
    why: str
    """Pydantic's message, without the ``Value error, `` prefix of a validator's ValueError."""
    more: int
    """How many further problems the error holds."""


def first_problem(exc: ValidationError) -> Problem:
    """Where and why validation failed first: the one way every module words a
    ``ValidationError`` (options and data files alike)."""
    err = exc.errors()[0]
    where = ""
    for part in err["loc"]:
        where += f"[{part}]" if isinstance(part, int) else (f".{part}" if where else str(part))
    why = str(err["msg"]).removeprefix("Value error, ")
    return Problem(where, why, exc.error_count() - 1)


def option_error(exc: ValidationError, what: str) -> ConfigError:
    """A one-line :class:`ConfigError` for invalid options: ``invalid <what> <field>: <why>``
    (just the reason when the options as a whole are wrong)."""
    where, why, _ = first_problem(exc)
    return ConfigError(f"invalid {what} {where}: {why}" if where else why)
