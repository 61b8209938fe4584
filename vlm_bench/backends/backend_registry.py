"""The backend registry, entry-point plug-ins, and the model-string rules.

Model strings: ``oracle``, ``random``, ``blind``, ``rules``, ``mock`` select the built-ins;
``openai/<name>`` and ``vllm/<id>`` select those backends; ``<plugin>/<model>`` (or a bare
``<plugin>``) selects a backend added through the ``vlm_bench.backends`` entry-point group;
a model card's name (``qwen2.5-vl-7b``, see ``vlm-bench models``) selects the card's backend,
checkpoint and ``-M`` arguments, and ``vllm/<card>`` or ``openai/<card>`` the card with that
backend; anything else (a Hugging Face id ``org/name`` or a local path) selects ``hf``. A bare
name that is none of these is an error. Write ``./vllm/x`` (``./qwen2.5-vl-7b``) for a local
folder whose name starts like a backend (or is a card's name).
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from importlib import import_module
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path

from vlm_bench.backends.backend import Backend
from vlm_bench.catalog.model_cards import model_cards
from vlm_bench.errors import ConfigError
from vlm_bench.registry import Registry
from vlm_bench.types.backend_table import BUILTIN_BACKENDS, BuiltinBackend
from vlm_bench.types.model_card import ModelCard

ENTRY_POINT_GROUP = "vlm_bench.backends"

BackendFactory = Callable[[str, Mapping[str, str]], Backend]
"""Builds a backend from a model name and raw ``-M key=value`` strings."""


@dataclass(frozen=True)
class BackendEntry:
    """A registered backend."""

    factory: BackendFactory
    takes_model: bool
    """Selected by ``<name>/<model>`` (True) or only by the bare name (False)."""
    description: str
    plugin: Callable[[], object] | None = None
    """A plug-in's entry point loader (its target: a Backend subclass or a factory)."""
    builtin: BuiltinBackend | None = None
    """A built-in's row of the backend table (None for a plug-in)."""


def _lazy(module: str, cls: str) -> BackendFactory:
    """Factory that imports the backend's module only when the backend is built."""

    def create(model: str, args: Mapping[str, str]) -> Backend:
        backend_cls: type[Backend] = getattr(import_module(module), cls)
        return backend_cls.from_args(model, args)

    return create


BACKENDS: Registry[BackendEntry] = Registry("backend")
for _row in BUILTIN_BACKENDS:
    BACKENDS.add(
        _row.name,
        BackendEntry(
            _lazy(f"vlm_bench.backends.{_row.module}", _row.cls),
            _row.prefix,
            _row.description,
            builtin=_row,
        ),
    )
_BUILTINS = frozenset(BACKENDS.names())
_plugins_loaded = False


def operational_args(model: str) -> frozenset[str]:
    """The ``-M`` arguments of the backend ``model`` selects that cannot change an answer
    (:data:`~vlm_bench.backends.backend.OPERATIONAL`); nothing is built, no heavy import.

    Empty for a plug-in factory function and for a model string no backend serves (the run's
    own checks report that).
    """
    try:
        name, _ = split_model(model)
        row = BACKENDS.get(name).builtin
        backend = builtin_class(row) if row is not None else plugin_backend_class(name)
    except ConfigError:
        return frozenset()
    return backend.Args.operational_fields() if backend is not None else frozenset()


def backend_entry(name: str) -> BackendEntry:
    """The registered backend ``name`` (built-in or plug-in); raises listing the valid names."""
    return BACKENDS.get(name)


def builtin_class(row: BuiltinBackend) -> type[Backend]:
    """The Backend subclass of a built-in (its module imported, nothing built)."""
    found: type[Backend] = getattr(import_module(f"vlm_bench.backends.{row.module}"), row.cls)
    return found


def plugin_backend_class(name: str) -> type[Backend] | None:
    """The Backend subclass of the plug-in registered as ``name`` (its module imported, nothing
    built); None for a built-in or a plug-in that is a factory function.

    Raises:
        ConfigError: The plug-in's target is neither a Backend subclass nor a factory.
    """
    plugin = BACKENDS.get(name).plugin
    if plugin is None:
        return None
    target = plugin()
    if isinstance(target, type) and issubclass(target, Backend):
        return target
    if callable(target):
        return None
    raise _not_a_backend(name)


def _not_a_backend(name: str) -> ConfigError:
    return ConfigError(
        f"entry point {name!r} ({BACKENDS.get(name).description}) must be a Backend subclass or "
        "a factory (model, args) -> Backend"
    )


def _plugin_factory(ep: EntryPoint) -> BackendFactory:
    def create(model: str, args: Mapping[str, str]) -> Backend:
        cls = plugin_backend_class(ep.name)
        if cls is not None:
            return cls.from_args(model, args)
        backend = ep.load()(model, args)
        if isinstance(backend, Backend):
            return backend
        raise _not_a_backend(ep.name)

    return create


def load_plugins() -> None:
    """Register the ``vlm_bench.backends`` entry points (once; their modules load on use).

    Raises:
        DuplicateNameError: Two plug-ins, or a plug-in and a built-in, share a name.
    """
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    for ep in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda e: (e.name, e.value)):
        entry = BackendEntry(_plugin_factory(ep), True, f"plug-in {ep.value}", ep.load)
        BACKENDS.add(ep.name, entry)


def card_for(model: str) -> ModelCard | None:
    """The model card a model string names (``<card>`` or ``<backend>/<card>``), if any."""
    cards = model_cards()
    prefix, sep, rest = model.partition("/")
    if not sep:
        return cards.get(model)
    if prefix in BACKENDS and BACKENDS.get(prefix).takes_model:
        return cards.get(rest)
    return None


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


def _unknown_bare_name(model: str) -> ConfigError:
    bare = [n for n in BACKENDS.names() if n not in _BUILTINS or not BACKENDS.get(n).takes_model]
    names = sorted(bare) + sorted(model_cards())
    close = difflib.get_close_matches(model.lower(), names, n=1, cutoff=0.6)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return ConfigError(
        f"unknown model {model!r}: not a backend, a model card or a local folder; {hint}give "
        f"{_selectors()}, or one of: {', '.join(names)}"
    )


def _selectors() -> str:
    """The model strings of the backends selected by a prefix, and of ``hf``."""
    rows = [row for row in BUILTIN_BACKENDS if row.prefix or row.name == "hf"]
    return ", ".join(row.selector for row in sorted(rows, key=lambda row: row.prefix))


def split_model(model: str) -> tuple[str, str]:
    """Apply the model-string rules: ``(backend name, model name for that backend)``.

    Raises:
        ConfigError: An empty string, or a bare name that is no backend, card or local folder.
    """
    load_plugins()
    if model in BACKENDS and model != "hf":
        return model, ""
    if not model:
        raise ConfigError(
            f"empty model string; give {_selectors()}, or one of: "
            f"{', '.join(sorted(_BUILTINS - {'hf'}))}"
        )
    card = card_for(model)
    prefix, sep, rest = model.partition("/")
    if sep and prefix in BACKENDS and BACKENDS.get(prefix).takes_model:
        return prefix, card.hub_id if card is not None else rest
    if card is not None:
        return card.backend, card.hub_id
    if not sep and not Path(model).exists():
        raise _unknown_bare_name(model)
    return "hf", model


def resolve_backend(model: str, args: Mapping[str, str] | None = None) -> Backend:
    """Build the backend a model string selects, with its ``-M key=value`` arguments.

    Args:
        model: A built-in's name or ``<name>/<model>``, ``<plugin>/<model>``, a model card's
            name, or a HF id / local path (``hf``); see
            :func:`~vlm_bench.types.backend_table.model_string_help`.
        args: Raw ``-M`` strings; each backend validates them against its own args model. For a
            model card they are added to the card's own (given keys win).

    Raises:
        ConfigError: Unknown or invalid arguments (the message lists the valid keys).
        MissingExtraError: The backend's optional dependency is not installed.
    """
    name, model_name = split_model(model)
    card = card_for(model)
    merged = {**(card.args_for(name) if card is not None else {}), **dict(args or {})}
    return BACKENDS.get(name).factory(model_name, merged)


def parse_model_args(pairs: list[str] | tuple[str, ...]) -> dict[str, str]:
    """Parse repeated ``key=value`` strings (the CLI's ``-M``); later keys win.

    Raises:
        ConfigError: An item without ``=`` or with an empty key.
    """
    out: dict[str, str] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.strip():
            raise ConfigError(f"-M expects key=value, got {pair!r}")
        out[key.strip()] = value
    return out
