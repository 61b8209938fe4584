"""Plans in the paper's JSON format, and the direction vocabulary."""

from __future__ import annotations

from collections.abc import Sequence
from enum import StrEnum
from typing import Annotated, Any, Literal

from pydantic import Field

from vlm_bench.types.base import Frozen


class Direction(StrEnum):
    """UAV move directions in the UAV body frame (x forward, y left, z up)."""

    FRONT = "front"
    FRONTLEFT = "frontleft"
    LEFT = "left"
    BACKLEFT = "backleft"
    BACK = "back"
    BACKRIGHT = "backright"
    RIGHT = "right"
    FRONTRIGHT = "frontright"
    UP = "up"
    DOWN = "down"

    @property
    def is_horizontal(self) -> bool:
        """True for the eight compass sectors, False for up/down."""
        return self not in (Direction.UP, Direction.DOWN)

    @property
    def angle_deg(self) -> float:
        """Bearing of a horizontal direction in the body frame, counter-clockwise from front."""
        if not self.is_horizontal:
            raise ValueError(f"{self.value} has no horizontal bearing")
        return 45.0 * HORIZONTAL_DIRECTIONS.index(self)


HORIZONTAL_DIRECTIONS: tuple[Direction, ...] = (
    Direction.FRONT,
    Direction.FRONTLEFT,
    Direction.LEFT,
    Direction.BACKLEFT,
    Direction.BACK,
    Direction.BACKRIGHT,
    Direction.RIGHT,
    Direction.FRONTRIGHT,
)


class UavStep(Frozen):
    """A UAV move in one of ten body-frame directions."""

    tasktype: Literal["UAV"] = "UAV"
    direction: Direction
    distance: float | None = Field(default=None, gt=0, description="Optional distance (m).")


class ArmStep(Frozen):
    """An ARM skill applied to an object (and optional target)."""

    tasktype: Literal["ARM"] = "ARM"
    object: str = Field(description="Object id the skill acts on.")
    skill: str = Field(description="Skill name from the skill library.")
    target: str | None = Field(default=None, description="Optional second object (push).")


PlanStep = Annotated[UavStep | ArmStep, Field(discriminator="tasktype")]

PlanSteps = Sequence[UavStep | ArmStep]
"""A plan's validated steps, in order (what the executor takes)."""


def plan_to_json(
    steps: list[UavStep | ArmStep] | tuple[UavStep | ArmStep, ...],
) -> list[dict[str, Any]]:
    """Serialise a plan in the paper's format, numbering subtasks from 0."""
    out: list[dict[str, Any]] = []
    for i, step in enumerate(steps):
        row: dict[str, Any] = {"subtask": i, "tasktype": step.tasktype}
        if isinstance(step, UavStep):
            row["direction"] = step.direction.value
            if step.distance is not None:
                row["distance"] = step.distance
        else:
            row["object"] = step.object
            row["skill"] = step.skill
            if step.target is not None:
                row["target"] = step.target
        out.append(row)
    return out
