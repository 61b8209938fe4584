"""The skill library as template context for the prompt's skill section (generated, never typed).

The plan JSON Schema for constrained decoding is ``vlm_bench.parsing.plan_json_schema``.
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from typing import Any

from vlm_bench.catalog.skills import skills
from vlm_bench.types.skill import SkillField, SkillSpec

_PLACEHOLDER = {"object": "<object id>", "direction": "<direction>", "number": "<metres>"}


def _uav_skill_count() -> int:
    return sum(1 for s in skills().values() if s.agent == "UAV")


def step_shape(skill: SkillSpec, *, optional: bool = False) -> dict[str, Any]:
    """The JSON shape of a plan step using ``skill``, with placeholders for its values.

    A UAV step has no ``skill`` key while ``move`` is the only UAV skill (the paper's format).
    """
    shape: dict[str, Any] = {"tasktype": skill.agent}
    for field in skill.fields:
        if field.required or optional:
            shape[field.name] = _PLACEHOLDER[field.type]
    if skill.agent == "ARM" or _uav_skill_count() > 1:
        shape["skill"] = skill.name
    return shape


def _field_row(field: SkillField) -> dict[str, Any]:
    return {
        "name": field.name,
        "required": field.required,
        "description": field.description,
        "values": list(field.values) if field.values else [],
    }


def skill_rows() -> list[dict[str, Any]]:
    """Template context for the prompt's skill section, in library order (UAV skills first)."""
    ordered = sorted(skills().values(), key=lambda s: s.agent != "UAV")
    return [
        {
            "name": s.name,
            "agent": s.agent,
            "description": s.description,
            "shape": step_shape(s),
            "fields": [_field_row(f) for f in s.fields],
        }
        for s in ordered
    ]


@cache
def skills_digest() -> str:
    """sha256 of the skill library's content (hashed into every prompt), less each skill's
    effect model: that shapes the plans planners write, not the prompt or how it is parsed."""
    data = [s.model_dump(mode="json", exclude={"effect"}) for s in skills().values()]
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()
