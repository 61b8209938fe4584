"""The plan JSON Schema, generated from the skill library.

One step variant per agent (``tasktype`` const): the agent's skills as an enum (required when
the agent has more than one skill, so the paper's UAV steps need no ``skill``), the union of
its skills' fields (required when every skill of the agent requires it), and an optional
``subtask`` number. Object fields are an enum of the scene's ids when they are given.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from jsonschema import Draft202012Validator, TypeChecker, validators
from jsonschema.protocols import Validator

from vlm_bench.catalog.skills import skills
from vlm_bench.errors import DataFileError
from vlm_bench.types.skill import SkillField, SkillSpec

SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"
MAX_PLAN_STEPS = 24
"""Most steps a plan may have: twice the longest GT plan (12 steps since tables stand at varied
heights; a test holds the bound to it). The bound lets a grammar-
constrained decoder close the array instead of adding steps until the token budget ends."""


def _field_schema(fld: SkillField, object_ids: Sequence[str] | None) -> dict[str, Any]:
    out: dict[str, Any]
    if fld.type == "object":
        out = {"type": "string"}
        if object_ids is not None:
            out["enum"] = list(dict.fromkeys(object_ids))
    elif fld.type == "direction":
        out = {"type": "string"}
        if fld.values is not None:
            out["enum"] = list(fld.values)
    else:  # number: distances and other magnitudes are positive
        out = {"type": "number", "exclusiveMinimum": 0}
    out["description"] = fld.description
    return out


def _agent_fields(specs: Sequence[SkillSpec]) -> tuple[dict[str, SkillField], list[str]]:
    """Union of the agent's fields by name, and the names every skill requires, in order."""
    fields: dict[str, SkillField] = {}
    for spec in specs:
        for fld in spec.fields:
            seen = fields.setdefault(fld.name, fld)
            if (seen.type, seen.values) != (fld.type, fld.values):
                raise DataFileError(
                    f"skills/{spec.name}.json", f"field {fld.name!r} differs from another skill's"
                )
    required = [
        name
        for name in fields
        if all(any(f.name == name and f.required for f in spec.fields) for spec in specs)
    ]
    return fields, required


def step_json_schema(agent: str, object_ids: Sequence[str] | None = None) -> dict[str, Any]:
    """JSON Schema of one step performed by ``agent`` (``UAV`` or ``ARM``)."""
    specs = [s for s in skills().values() if s.agent == agent]
    fields, required = _agent_fields(specs)
    properties: dict[str, Any] = {
        "subtask": {
            "type": "integer",
            "minimum": 0,
            "description": "Step number from 0 (ignored: order is the array order).",
        },
        "tasktype": {"const": agent, "description": "Which agent performs the step."},
        "skill": {
            "type": "string",
            "enum": [s.name for s in specs],
            "description": "Skill from the skill library.",
        },
    }
    for name, fld in fields.items():
        properties[name] = _field_schema(fld, object_ids)
    skill_required = ["skill"] if len(specs) > 1 else []
    return {
        "title": f"{agent} step",
        "type": "object",
        "properties": properties,
        "required": ["tasktype", *skill_required, *required],
        "additionalProperties": False,
    }


def plan_json_schema(
    object_ids: Sequence[str] | None = None, *, max_steps: int | None = MAX_PLAN_STEPS
) -> dict[str, Any]:
    """JSON Schema of a plan: a non-empty array of steps, one variant per agent.

    Args:
        object_ids: The scene's object (and part) ids; when given, ``object``/``target`` must be
            one of them.
        max_steps: ``maxItems`` of the array (None: unbounded). Constrained decoding needs the
            bound; the parser's ``valid`` tier judges form, not length, and leaves it out.

    Returns:
        A JSON Schema (draft 2020-12) as a dict, fit for constrained decoding and validation.
    """
    agents = list(dict.fromkeys(s.agent for s in skills().values()))
    schema: dict[str, Any] = {
        "$schema": SCHEMA_DIALECT,
        "title": "Plan",
        "description": "Steps in execution order.",
        "type": "array",
        "minItems": 1,
        "items": {"anyOf": [step_json_schema(agent, object_ids) for agent in agents]},
    }
    if max_steps is not None:
        schema["maxItems"] = max_steps
    return schema


def _finite_number(checker: TypeChecker, value: object) -> bool:
    # JSON has no NaN or Infinity; a float of either is not a JSON number.
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, int) and not isinstance(value, bool)


_Validator = validators.extend(  # type: ignore[no-untyped-call]
    Draft202012Validator,
    type_checker=Draft202012Validator.TYPE_CHECKER.redefine("number", _finite_number),
)


def schema_validator(schema: Mapping[str, Any]) -> Validator:
    """A ``jsonschema`` validator of ``schema`` (draft 2020-12, JSON number semantics)."""
    validator: Validator = _Validator(schema)
    return validator


def schema_violations(schema: Mapping[str, Any], value: Any) -> list[str]:
    """Violations of ``schema`` by ``value`` as ``"<path>: <keyword>: <message>"`` (empty when
    valid); the keyword is the schema keyword that failed (``type``, ``anyOf``, ``minItems`` …)."""
    return [
        f"{e.json_path}: {e.validator}: {e.message}"
        for e in schema_validator(schema).iter_errors(value)
    ]


def is_valid(schema: Mapping[str, Any], value: Any) -> bool:
    """True when ``value`` satisfies ``schema``."""
    return bool(schema_validator(schema).is_valid(value))
