"""Checks of a model string and its ``-M`` arguments that load no model and call no server.

A run calls :func:`check_backend` before it writes its folder or renders a snapshot, so a typo
in ``--model``, a bad ``-M`` key or value, a missing scripted-output file or a missing extra
leaves nothing behind and the corrected command starts clean.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import import_module
from importlib.util import find_spec

from vlm_bench.backends.backend import Backend, parse_args
from vlm_bench.backends.backend_registry import (
    BACKENDS,
    card_for,
    plugin_backend_class,
    split_model,
)
from vlm_bench.backends.model_source import check_model_source
from vlm_bench.errors import ConfigError, MissingExtraError

WEIGHTLESS = frozenset({"oracle", "random", "blind", "rules", "mock"})
"""Built-ins cheap enough to build outright as their check (they read at most a small file)."""

_MODEL_BACKENDS: dict[str, tuple[str, str, tuple[str, ...], str]] = {
    # backend: (module under vlm_bench.backends, class, what its constructor imports, extra)
    "hf": ("hf", "HfBackend", ("torch", "transformers"), "hf"),
    "vllm": ("vllm_backend", "VllmBackend", ("vllm",), "vllm"),
    "openai": ("openai_backend", "OpenAIBackend", ("openai",), "openai"),
}


@dataclass(frozen=True)
class BackendCheck:
    """What the checks found out about a model string."""

    name: str
    """The backend that serves it (``hf``, ``openai``, ``oracle``, a plug-in, ...)."""
    model: str
    """The model name that backend gets (a hub id, a path, a served name, or empty)."""
    loads_model: bool
    """A model runs in this process (``hf``, ``vllm`` and plug-ins): torch and friends load."""
    sees_images: bool = True
    """Its answers may depend on images (:attr:`.Backend.sees_images`)."""


def loads_model_in_process(backend: str) -> bool:
    """True unless ``backend`` is a weightless built-in or a client of a server (``openai``)."""
    return backend not in WEIGHTLESS and backend != "openai"


def did_you_mean(model: str) -> str:
    """``"; did you mean 'openai/x'?"`` when ``model`` is one typo from a backend, else ``""``."""
    prefix, sep, rest = model.partition("/")
    if sep:
        names = [n for n in BACKENDS.names() if BACKENDS.get(n).takes_model]
        close = difflib.get_close_matches(prefix.lower(), names, n=1, cutoff=0.7)
        return f"; did you mean '{close[0]}/{rest}'?" if close else ""
    names = [n for n in BACKENDS.names() if n != "hf"]
    close = difflib.get_close_matches(model.lower(), names, n=1, cutoff=0.7)
    return f"; did you mean {close[0]!r}?" if close else ""


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


def _backend_class(name: str) -> type[Backend]:
    module, cls, _, _ = _MODEL_BACKENDS[name]
    found: type[Backend] = getattr(import_module(f"vlm_bench.backends.{module}"), cls)
    return found


def check_backend(
    model: str, args: Mapping[str, str] | None = None, *, constrained: bool = False
) -> BackendCheck:
    """Check everything about a backend that needs no model, no server and no simulator.

    Builds the weightless built-ins outright; for ``hf``, ``vllm`` and ``openai`` checks that
    the extra is installed, validates the ``-M`` arguments (finite numbers only) and, for
    ``hf``/``vllm``, that the model is a local folder or a Hugging Face id the cache or the
    hub knows. A plug-in's module is imported and, where it is a Backend subclass, its ``-M``
    arguments validated against its ``Args`` (a factory function's are checked when it builds).

    Args:
        model: The model string (``--model``).
        args: Raw ``-M key=value`` strings.
        constrained: The run decodes under a JSON Schema (``hf`` then needs xgrammar).

    Raises:
        ConfigError: An unknown model, a bad argument, a missing file (one line).
        MissingExtraError: The backend's optional dependency is not installed.
    """
    name, model_name = split_model(model)
    card = card_for(model)
    raw = {**(card.args_for(name) if card is not None else {}), **dict(args or {})}
    if name in WEIGHTLESS:
        built = BACKENDS.get(name).factory(model_name, raw)
        built.close()
        return BackendCheck(name, model_name, loads_model=False, sees_images=built.sees_images)
    if name not in _MODEL_BACKENDS:
        _check_plugin_args(name, raw)
        return BackendCheck(name, model_name, loads_model_in_process(name))
    _, _, requires, extra = _MODEL_BACKENDS[name]
    if any(find_spec(module) is None for module in requires):
        raise MissingExtraError(" and ".join(requires), extra)
    if constrained and name == "hf" and find_spec("xgrammar") is None:
        raise MissingExtraError("xgrammar", "constrained")
    cls = _backend_class(name)
    parsed = parse_args(cls.name, cls.Args, raw)
    _require_finite(name, parsed)
    if not model_name:
        raise ConfigError(f"backend {name!r} needs a model: --model {name}/<model>")
    if name != "openai":
        check_model_source(
            model_name,
            getattr(parsed, "revision", None),
            hint=did_you_mean(model),
            needs_config=name == "hf",
        )
    return BackendCheck(name, model_name, loads_model_in_process(name))
