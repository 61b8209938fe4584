"""A small JSON Schema validator for the keywords :mod:`vlm_bench.parsing.schema` emits.

The package does not depend on ``jsonschema``; the plan schema uses a handful of keywords, all
implemented here with JSON (not Python) semantics: ``true`` is not an integer, ``1.0`` is.
A schema using any other assertion keyword is a programming error and raises ``ValueError``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

_ANNOTATIONS = frozenset({"$schema", "title", "description"})


def _is_number(value: Any) -> bool:
    if isinstance(value, bool):
        return False
    return isinstance(value, int) or (isinstance(value, float) and math.isfinite(value))


def _is_integer(value: Any) -> bool:
    if isinstance(value, int):
        return not isinstance(value, bool)
    return _is_number(value) and float(value).is_integer()


_TYPES: Mapping[str, Callable[[Any], bool]] = {
    "array": lambda v: isinstance(v, list),
    "object": lambda v: isinstance(v, dict),
    "string": lambda v: isinstance(v, str),
    "number": _is_number,
    "integer": _is_integer,
    "boolean": lambda v: isinstance(v, bool),
    "null": lambda v: v is None,
}


def _same(a: Any, b: Any) -> bool:
    """JSON equality: booleans never equal numbers."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    return bool(a == b)


def schema_violations(schema: Mapping[str, Any], value: Any, path: str = "$") -> list[str]:
    """Return human-readable violations of ``schema`` by ``value`` (empty when valid)."""
    out: list[str] = []
    for key, rule in schema.items():
        if key in _ANNOTATIONS or key in ("properties", "additionalProperties"):
            continue
        if key == "type":
            if not _TYPES[rule](value):
                out.append(f"{path}: expected {rule}")
                return out  # other keywords assume the type
        elif key == "enum":
            if not any(_same(value, v) for v in rule):
                out.append(f"{path}: {value!r} is not one of {rule}")
        elif key == "const":
            if not _same(value, rule):
                out.append(f"{path}: expected {rule!r}")
        elif key == "required":
            missing = [k for k in rule if isinstance(value, dict) and k not in value]
            out.extend(f"{path}: missing {k!r}" for k in missing)
        elif key == "minItems":
            if isinstance(value, list) and len(value) < rule:
                out.append(f"{path}: fewer than {rule} items")
        elif key == "maxItems":
            if isinstance(value, list) and len(value) > rule:
                out.append(f"{path}: more than {rule} items")
        elif key == "minimum":
            if _is_number(value) and value < rule:
                out.append(f"{path}: below {rule}")
        elif key == "exclusiveMinimum":
            if _is_number(value) and value <= rule:
                out.append(f"{path}: not above {rule}")
        elif key == "items":
            if isinstance(value, list):
                for i, item in enumerate(value):
                    out.extend(schema_violations(rule, item, f"{path}[{i}]"))
        elif key in ("anyOf", "oneOf"):
            passing = sum(not schema_violations(sub, value, path) for sub in rule)
            if passing == 0 or (key == "oneOf" and passing > 1):
                out.append(f"{path}: matches {passing} of the {key} variants")
        else:
            raise ValueError(f"unsupported JSON Schema keyword {key!r}")
    if isinstance(value, dict):
        out.extend(_object_violations(schema, value, path))
    return out


def _object_violations(schema: Mapping[str, Any], value: dict[str, Any], path: str) -> list[str]:
    out: list[str] = []
    properties: Mapping[str, Any] = schema.get("properties", {})
    for key, item in value.items():
        if key in properties:
            out.extend(schema_violations(properties[key], item, f"{path}.{key}"))
        elif schema.get("additionalProperties", True) is False:
            out.append(f"{path}: unexpected key {key!r}")
    return out


def is_valid(schema: Mapping[str, Any], value: Any) -> bool:
    """True when ``value`` satisfies ``schema``."""
    return not schema_violations(schema, value)
