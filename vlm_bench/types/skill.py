"""Skill library entries (``skills/<name>.json``): the single source of truth for skills."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from vlm_bench.types.base import Frozen
from vlm_bench.types.world import SNAKE

FieldType = Literal["object", "direction", "number"]

STEP_FIELDS: dict[str, dict[str, FieldType]] = {
    "UAV": {"direction": "direction", "distance": "number"},
    "ARM": {"object": "object", "target": "object"},
}
"""The fields a plan step of each agent carries (:class:`~vlm_bench.types.plan.UavStep`,
:class:`~vlm_bench.types.plan.ArmStep`, less ``tasktype`` and ``skill``), with their types: a
skill declares only these, so every field it declares reaches the plan (a new kind of field is a
field of the step model first)."""


class SkillField(Frozen):
    """A field a plan step of this skill carries."""

    name: str = Field(pattern=SNAKE, description="JSON key in the plan step.")
    type: FieldType = Field(description="What the value is.")
    required: bool = Field(description="The step is invalid without it.")
    description: str = Field(description="One line for the prompt.")
    values: tuple[str, ...] | None = Field(
        default=None, description="Allowed values (closed vocabularies such as directions)."
    )
    value_aliases: dict[str, tuple[str, ...]] = Field(
        default_factory=dict, description="Canonical value → accepted spellings (normalised)."
    )


class SkillSpec(Frozen):
    """One skill of the library: how it is prompted, validated and executed."""

    name: str = Field(pattern=SNAKE, description="Canonical name used in plans.")
    agent: Literal["UAV", "ARM"] = Field(description="Which agent performs it (plan tasktype).")
    description: str = Field(description="What it does, for the prompt.")
    aliases: tuple[str, ...] = Field(default=(), description="Other names models use for it.")
    fields: tuple[SkillField, ...] = Field(description="Fields of a plan step using this skill.")
    preconditions: tuple[str, ...] = Field(default=(), description="What must hold before.")
    effects: tuple[str, ...] = Field(default=(), description="What holds after success.")
    applies_to: tuple[str, ...] = Field(
        default=(), description="Object/part kinds it applies to (empty = any graspable object)."
    )
    effect: str = Field(
        default="none",
        pattern=SNAKE,
        description="Its effect model on the planning state (vlm_bench.rules.effects: hold, "
        "release, open, shut, slide, none).",
    )

    @model_validator(mode="after")
    def _fields_a_step_carries(self) -> SkillSpec:
        carried = STEP_FIELDS[self.agent]
        for fld in self.fields:
            if carried.get(fld.name) != fld.type:
                valid = ", ".join(f"{n} ({t})" for n, t in carried.items())
                raise ValueError(
                    f"field {fld.name!r} ({fld.type}) is not one that {self.agent} plan steps "
                    f"carry; valid: {valid}"
                )
        return self
