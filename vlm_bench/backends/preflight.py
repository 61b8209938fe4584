"""Checks of a model string and its ``-M`` arguments that load no model and call no server.

A run calls :func:`check_backend` before it writes its folder or renders a snapshot, so a typo
in ``--model``, a bad ``-M`` key or value, a missing scripted-output file or a missing extra
leaves nothing behind and the corrected command starts clean.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from importlib.util import find_spec

from vlm_bench.backends.backend import parse_args
from vlm_bench.backends.backend_registry import (
    backend_entry,
    builtin_class,
    card_for,
    did_you_mean,
    plugin_backend_class,
    split_model,
)
from vlm_bench.backends.model_source import check_model_source
from vlm_bench.errors import ConfigError, MissingExtraError


@dataclass(frozen=True)
class BackendCheck:
    """What the checks found out about a model string."""

    name: str
    """The backend that serves it (``hf``, ``openai``, ``oracle``, a plug-in, ...)."""
    model: str
    """The model name that backend gets (a hub id, a path, a served name, or empty)."""
    sees_images: bool = True
    """Its answers may depend on images (:attr:`.Backend.sees_images`)."""


def _require_finite(backend: str, args: object) -> None:
    for key, value in vars(args).items():
        if isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(
                f"invalid -M argument {key}={value} for backend {backend!r}: must be a finite "
                "number"
            )


def _check_plugin_args(name: str, raw: Mapping[str, str]) -> None:
    """Validate a plug-in backend's ``-M`` arguments against its ``Args`` (no model built)."""
    cls = plugin_backend_class(name)
    if cls is not None:
        _require_finite(name, parse_args(cls.name, cls.Args, raw))


def check_backend(
    model: str, args: Mapping[str, str] | None = None, *, constrained: bool = False
) -> BackendCheck:
    """Check everything about a backend that needs no model, no server and no simulator.

    What it checks of a built-in, its row of the backend table says
    (:data:`~vlm_bench.types.backend_table.BUILTIN_BACKENDS`): a weightless one is built
    outright; for the others, that the modules it imports (and those constrained decoding
    needs) are installed, the ``-M`` arguments (finite numbers only) and, where the row asks,
    that the model is a local folder or a Hugging Face id the cache or the hub knows. A
    plug-in's module is imported and, where it is a Backend subclass, its ``-M`` arguments
    validated against its ``Args`` (a factory function's are checked when it builds).

    Args:
        model: The model string (``--model``).
        args: Raw ``-M key=value`` strings.
        constrained: The run decodes under a JSON Schema.

    Raises:
        ConfigError: An unknown model, a bad argument, a missing file (one line).
        MissingExtraError: The backend's optional dependency is not installed.
    """
    name, model_name = split_model(model)
    card = card_for(model)
    raw = {**(card.args_for(name) if card is not None else {}), **dict(args or {})}
    entry = backend_entry(name)
    row = entry.builtin
    if row is None:
        _check_plugin_args(name, raw)
        return BackendCheck(name, model_name)
    if row.runs == "weightless":
        built = entry.factory(model_name, raw)
        built.close()
        return BackendCheck(name, model_name, sees_images=built.sees_images)
    if any(find_spec(module) is None for module in row.requires):
        raise MissingExtraError(" and ".join(row.requires), row.extra or name)
    needed = row.constrained_requires if constrained else ()
    if any(find_spec(module) is None for module in needed):
        raise MissingExtraError(" and ".join(needed), "constrained")
    cls = builtin_class(row)
    parsed = parse_args(cls.name, cls.Args, raw)
    _require_finite(name, parsed)
    if not model_name:
        raise ConfigError(f"backend {name!r} needs a model: --model {name}/<model>")
    if row.model_check != "none":
        check_model_source(
            model_name,
            getattr(parsed, "revision", None),
            hint=did_you_mean(model),
            needs_config=row.model_check == "local_or_hub_config",
        )
    return BackendCheck(name, model_name, sees_images=cls.sees_images)
