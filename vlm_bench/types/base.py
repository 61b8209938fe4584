"""Small shared types: the base of every data model and the vector aliases used across layers."""

from __future__ import annotations

from collections.abc import Collection
from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import AfterValidator, BaseModel, ConfigDict

Vec3 = tuple[float, float, float]
"""A point or direction in metres (x, y, z), as stored in data files."""
RGBA = tuple[float, float, float, float]
"""A colour with alpha, each channel in [0, 1]."""
FloatArray = NDArray[np.float64]
"""A float64 numpy array (positions, joint angles, rotation matrices) inside the simulator."""


def utf8_text(value: str) -> str:
    """``value`` as UTF-8 can hold it: surrogate pairs joined, lone surrogates (which JSON
    escapes and undecodable command-line bytes produce) replaced by U+FFFD."""
    if value.isascii():
        return value
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        return value.encode("utf-16", "surrogatepass").decode("utf-16", "replace")
    return value


Utf8Str = Annotated[str, AfterValidator(utf8_text)]
"""Text from outside (model answers, server messages) as stored: see :func:`utf8_text`."""


class Frozen(BaseModel):
    """Base for immutable data models that reject unknown fields."""

    model_config = ConfigDict(frozen=True, extra="forbid")


class FiniteFrozen(Frozen):
    """A :class:`Frozen` model whose floats must be finite: what is written to JSON files
    (records, manifests), where NaN and infinity have no form."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)


def omit_none(data: Any, names: Collection[str]) -> Any:
    """``data`` (a model's serialised dict) without the keys of ``names`` whose value is None:
    a field added later is left out of the JSON while unset, so files written without it do
    not change."""
    if isinstance(data, dict):
        for name in names:
            if name in data and data[name] is None:
                del data[name]
    return data
