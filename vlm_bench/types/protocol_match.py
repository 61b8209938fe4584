"""Which stated protocol a run configuration is (:func:`protocol_of`), and a configuration
put under a protocol (:func:`with_protocol`, behind ``--protocol`` and ``vlm_bench.run``)."""

from __future__ import annotations

from collections.abc import Collection
from typing import Any

from pydantic import BaseModel

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.protocol import CUSTOM, PROTOCOLS, ProtocolMark, ProtocolName, ProtocolSpec
from vlm_bench.types.run import RunConfig, RunManifest, config_differences, run_config

SELECTION = ("tasks", "suite", "seeds", "instructions")
"""Fields that choose episodes: under a protocol they may narrow its episode set."""
FREE_GENERATION = ("max_new_tokens", "batch_size", "seed")
"""Decoding fields a protocol leaves free (greedy decoding ignores the sampling seed)."""


def reference_config(config: RunConfig, spec: ProtocolSpec) -> RunConfig:
    """``config`` with every field a protocol fixes set to the protocol's value."""
    free: dict[str, Any] = {name: getattr(config, name) for name in SELECTION}
    generation = GenerationConfig(
        **{name: getattr(config.generation, name) for name in FREE_GENERATION}
    )
    fields: dict[str, Any] = {
        "model": config.model,
        "backend_args": config.backend_args,
        "generation": generation,
        "execute": config.execute,
        "benchmark_version": config.benchmark_version,
        **free,
        **spec.settings,
    }
    return RunConfig(**fields)


def differences(config: RunConfig, spec: ProtocolSpec) -> list[str]:
    """Dotted names of the settings where ``config`` leaves ``spec`` (``seeds`` when it has a
    seed outside the protocol's)."""
    reference = reference_config(config, spec)
    out = config_differences(reference, config)
    if not set(config.seeds) <= set(spec.seeds):
        out.insert(0, "seeds")
    return out


def protocol_of(config: RunConfig) -> ProtocolName:
    """The stated protocol whose settings ``config`` has and whose episodes it stays within,
    or ``custom``."""
    for spec in PROTOCOLS.values():
        if not differences(config, spec):
            return spec.name
    return CUSTOM


def protocol_mark(config: RunConfig, episodes: int, all_tasks: int) -> ProtocolMark:
    """The mark a run records: its protocol and how many of the protocol's episodes it runs.

    Args:
        config: The run configuration.
        episodes: Episodes the run selects.
        all_tasks: Tasks of the benchmark (the protocol runs them all).
    """
    name = protocol_of(config)
    if name == CUSTOM:
        return ProtocolMark(name=name, episodes=episodes)
    spec = PROTOCOLS[name]
    total = all_tasks * len(spec.seeds) * 2
    return ProtocolMark(name=name, episodes=episodes, protocol_episodes=total)


def manifest_protocol(manifest: RunManifest) -> ProtocolMark:
    """The manifest's recorded protocol; for a manifest written before protocols were
    recorded, the protocol its configuration matches (episode counts unknown)."""
    if manifest.protocol is not None:
        return manifest.protocol
    return ProtocolMark(name=protocol_of(manifest.config))


_OPTIONS = {
    "instructions": "--instruction",
    "object_list": "--no-object-list",
    "images": "--no-images",
}


def _option(field: str) -> str:
    """The CLI option of a dotted field (decoding fields by their own name)."""
    parts = field.split(".")
    name = parts[-1] if parts[0] == "generation" else parts[0]
    return _OPTIONS.get(name, "--" + name.replace("_", "-"))


def with_protocol(config: RunConfig, name: str | None, given: Collection[str] = ()) -> RunConfig:
    """``config`` under the stated protocol ``name`` (None or ``custom``: unchanged).

    Fields not in ``given`` take the protocol's values (its seeds and both instructions too);
    given selection fields may narrow its episodes, any other given field must equal the
    protocol's value.

    Args:
        config: The configuration built from the options.
        name: ``paper``, ``closed``, ``custom`` or None.
        given: The RunConfig fields the user set explicitly (``generation`` for decoding).

    Raises:
        UnknownNameError: An unknown protocol name.
        ConfigError: A given option that the protocol fixes to another value, or a seed
            outside the protocol (names the option and the protocol's value).
    """
    if name is None or name == CUSTOM:
        return config
    if name not in PROTOCOLS:
        raise UnknownNameError("protocol", name, [*PROTOCOLS, CUSTOM])
    spec = PROTOCOLS[name]
    update: dict[str, Any] = {}
    if "seeds" not in given:
        update["seeds"] = spec.seeds
    if "instructions" not in given:
        update["instructions"] = ("explicit", "implicit")
    reference = reference_config(config.model_copy(update=update), spec)
    kept = {f for f in given if f not in SELECTION}
    for field in config_differences(reference, config):
        top = field.split(".")[0]
        if top in kept or top in SELECTION:
            continue
        update[top] = getattr(reference, top)
    resolved = run_config(**{**config.model_dump(), **update})
    wrong = differences(resolved, spec)
    if wrong:
        field = wrong[0]
        if field == "seeds":
            raise ConfigError(
                f"--protocol {name} takes seeds within {_shown(spec.seeds)}; got "
                f"{_shown(resolved.seeds)}"
            )
        raise ConfigError(
            f"--protocol {name} sets {_option(field)} to {_shown(_value(reference, field))}; "
            f"drop {_option(field)} or --protocol"
        )
    return resolved


def _value(config: RunConfig, dotted: str) -> Any:
    parts = dotted.split(".")
    value: Any = getattr(config, parts[0])
    if parts[0] == "generation":
        value = getattr(value, parts[-1])
    return value


def _shown(value: Any) -> str:
    if isinstance(value, BaseModel):
        return ",".join(f"{k}={v}" for k, v in value.model_dump().items())
    consecutive = isinstance(value, tuple) and value and all(isinstance(v, int) for v in value)
    if consecutive and list(value) == list(range(value[0], value[-1] + 1)):
        return f"{value[0]}-{value[-1]}"
    if isinstance(value, tuple):
        return ",".join(map(str, value))
    return str(value)
