"""Task specifications (``ground_truth/tasks/<suite>/<id>.json``)."""

from __future__ import annotations

from enum import StrEnum
from typing import Literal

from pydantic import Field, model_validator

from vlm_bench.types.base import Frozen
from vlm_bench.types.world import SNAKE


class Suite(StrEnum):
    """The paper's four task suites."""

    BASE = "base_manipulation"
    OBJECT_SPATIAL = "object_spatial"
    SEMANTIC = "semantic_understanding"
    LONG_HORIZON = "long_horizon"

    @property
    def label(self) -> str:
        """Human title as printed in the paper's tables."""
        return SUITE_TITLES[self]


SUITE_TITLES: dict[Suite, str] = {
    Suite.BASE: "Base Manipulation",
    Suite.OBJECT_SPATIAL: "Object & Spatial",
    Suite.SEMANTIC: "Semantic Understanding",
    Suite.LONG_HORIZON: "Long-Horizon",
}

InstructionVariant = Literal["explicit", "implicit"]
INSTRUCTION_VARIANTS: tuple[InstructionVariant, ...] = ("explicit", "implicit")

Role = Literal["target", "destination", "distractor", "support", "fixture"]
GoalPredicate = Literal[
    "inside",
    "on",
    "stacked_on",
    "upright",
    "drawer_open",
    "drawer_closed",
    "knob_rotated",
    "off_surface",
    "near",
]
# Predicates that relate two objects (need ``target``).
BINARY_PREDICATES: frozenset[str] = frozenset({"inside", "on", "stacked_on", "off_surface", "near"})


class PlacedObject(Frozen):
    """An object in a task's canonical layout (seed 0)."""

    id: str = Field(pattern=SNAKE, description="Id used in plans, e.g. yellow_basket, red_cup_1.")
    kind: str = Field(description="Object kind from the world catalogue.")
    color: str | None = Field(default=None, description="Named colour; None = the kind's default.")
    on: str = Field(default="floor", description="Id of the object it rests on, or 'floor'.")
    xy: tuple[float, float] = Field(description="World position of its centre (m) at seed 0.")
    yaw_deg: float = Field(default=0.0, description="Heading at seed 0 (deg); +x is its front.")
    role: Role = Field(description="What the object is for in this task.")
    fixed: bool = Field(default=False, description="Never jittered between seeds (furniture).")
    initial: dict[str, float] = Field(
        default_factory=dict,
        description="Initial joint state of parts: drawer opening (m) or knob angle (deg).",
    )


class ArmStepSpec(Frozen):
    """One ARM step of the task's plan skeleton; UAV steps are derived from geometry."""

    skill: str = Field(description="ARM skill name from the skill library.")
    object: str = Field(description="Id of the object (or part) the skill acts on.")
    target: str | None = Field(default=None, description="Optional second object (push target).")


class Goal(Frozen):
    """A predicate on the final state that the executor checks."""

    predicate: GoalPredicate
    object: str = Field(description="Id of the object (or part) the predicate is about.")
    target: str | None = Field(default=None, description="Second object for binary predicates.")

    @model_validator(mode="after")
    def _target_matches_arity(self) -> Goal:
        if (self.predicate in BINARY_PREDICATES) != (self.target is not None):
            need = "needs" if self.predicate in BINARY_PREDICATES else "takes no"
            raise ValueError(f"predicate {self.predicate!r} {need} a target")
        return self


class Instructions(Frozen):
    """The two hand-written instruction variants."""

    explicit: str = Field(min_length=8, description="Structured instruction naming objects.")
    implicit: str = Field(min_length=8, description="Conversational, implicit-intent instruction.")


class TaskSpec(Frozen):
    """One of the 60 benchmark tasks."""

    id: str = Field(pattern=SNAKE, description="Stable task id, e.g. standard_pick_place.")
    name: str = Field(description="Task name as in the paper's task list.")
    suite: Suite
    environment: str = Field(description="Environment variant from the world catalogue.")
    description: str = Field(description="What the task tests (the paper's summary).")
    objects: tuple[PlacedObject, ...] = Field(min_length=1)
    instructions: Instructions
    arm_steps: tuple[ArmStepSpec, ...] = Field(min_length=1)
    goals: tuple[Goal, ...] = Field(min_length=1)
