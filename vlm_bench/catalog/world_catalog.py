"""The world catalogue: colours, object kinds, environments."""

from __future__ import annotations

from functools import cache

from vlm_bench.catalog.files import load_model
from vlm_bench.errors import UnknownNameError
from vlm_bench.resources import ground_truth_dir
from vlm_bench.types.base import RGBA
from vlm_bench.types.world import EnvironmentSpec, ObjectKind, WorldCatalog


@cache
def world() -> WorldCatalog:
    """Load and validate ``ground_truth/world.json`` (cached)."""
    return load_model(ground_truth_dir() / "world.json", WorldCatalog)


def object_kinds() -> dict[str, ObjectKind]:
    """All object kinds by name."""
    return {k.name: k for k in world().object_kinds}


def object_kind(name: str) -> ObjectKind:
    """One object kind; raises listing the valid kinds."""
    kinds = object_kinds()
    if name not in kinds:
        raise UnknownNameError("object kind", name, kinds)
    return kinds[name]


def color(name: str) -> RGBA:
    """RGBA of a named colour; raises listing the valid colours."""
    colors = world().colors
    if name not in colors:
        raise UnknownNameError("colour", name, colors)
    return colors[name]


def environments() -> dict[str, EnvironmentSpec]:
    """All environment variants by name."""
    return {e.name: e for e in world().environments}


def environment(name: str) -> EnvironmentSpec:
    """One environment variant; raises listing the valid variants."""
    envs = environments()
    if name not in envs:
        raise UnknownNameError("environment", name, envs)
    return envs[name]
