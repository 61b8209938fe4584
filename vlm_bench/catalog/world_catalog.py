"""The world catalogue: colours, object kinds, environments."""

from __future__ import annotations

from functools import cache
from typing import Any

from vlm_bench.catalog.files import load_model
from vlm_bench.errors import UnknownNameError
from vlm_bench.resources import ground_truth_dir
from vlm_bench.types.base import RGBA
from vlm_bench.types.world import EnvironmentSpec, ObjectKind, WorldCatalog

_BY_NAME: dict[str, tuple[WorldCatalog, dict[str, Any]]] = {}
"""Lookups by name made from :func:`world`'s catalogue, with the catalogue they were made of."""


@cache
def world() -> WorldCatalog:
    """Load and validate ``ground_truth/world.json`` (cached)."""
    return load_model(ground_truth_dir() / "world.json", WorldCatalog)


def _kinds() -> dict[str, ObjectKind]:
    """All object kinds by name, made once per loaded catalogue (the executor looks kinds up
    ~10^5 times a sweep)."""
    w = world()
    made = _BY_NAME.get("kinds")
    if made is None or made[0] is not w:
        made = _BY_NAME["kinds"] = (w, {k.name: k for k in w.object_kinds})
    return made[1]


def object_kinds() -> dict[str, ObjectKind]:
    """All object kinds by name (a new dict: the caller may change it)."""
    return dict(_kinds())


def object_kind(name: str) -> ObjectKind:
    """One object kind; raises listing the valid kinds."""
    kinds = _kinds()
    if name not in kinds:
        raise UnknownNameError("object kind", name, kinds)
    return kinds[name]


def color(name: str) -> RGBA:
    """RGBA of a named colour; raises listing the valid colours."""
    colors = world().colors
    if name not in colors:
        raise UnknownNameError("colour", name, colors)
    return colors[name]


def _environments() -> dict[str, EnvironmentSpec]:
    """All environment variants by name, made once per loaded catalogue."""
    w = world()
    made = _BY_NAME.get("environments")
    if made is None or made[0] is not w:
        made = _BY_NAME["environments"] = (w, {e.name: e for e in w.environments})
    return made[1]


def environments() -> dict[str, EnvironmentSpec]:
    """All environment variants by name (a new dict: the caller may change it)."""
    return dict(_environments())


def environment(name: str) -> EnvironmentSpec:
    """One environment variant; raises listing the valid variants."""
    envs = _environments()
    if name not in envs:
        raise UnknownNameError("environment", name, envs)
    return envs[name]
