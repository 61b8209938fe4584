"""Closed-loop evaluation (docs/design.md#closed-loop): perturbations, and the rounds an episode
replans in after a failed execution.

An open-loop run writes none of these: the fields that hold them are left out of a record's
JSON while they are None (:func:`~vlm_bench.types.base.omit_none`), so an open-loop record is
byte-for-byte what it was before the closed loop existed.
"""

from __future__ import annotations

from typing import Literal

from pydantic import ConfigDict, Field, model_validator

from vlm_bench.types.base import FiniteFrozen
from vlm_bench.types.plan import PlanStep

LoopMode = Literal["open", "closed"]
"""``open``: one plan per episode (the paper's protocol); ``closed``: replan after failures."""

HistoryMode = Literal["text", "images"]
"""How a multi-turn replan shows earlier rounds: their text only (the current views alone as
images), or their views too."""


class PerturbConfig(FiniteFrozen):
    """Seeded failures a good plan cannot avoid (``--perturb slip=P,bump=P``; gusts are
    ``uav_noise``). A kind registered beyond slip and bump (docs/design.md#how-to-add-a-
    perturbation-kind) is one more field, given by its name."""

    model_config = ConfigDict(frozen=True, extra="allow", allow_inf_nan=False)

    slip: float = Field(
        default=0.0, ge=0, le=1, description="Chance a held object drops during a carry."
    )
    bump: float = Field(
        default=0.0,
        ge=0,
        le=1,
        description="Chance an ARM step's object is displaced 0.2-0.4 m before the step.",
    )

    @model_validator(mode="after")
    def _rates(self) -> PerturbConfig:
        for name, value in (self.model_extra or {}).items():
            if not isinstance(value, (int, float)) or not 0 <= value <= 1:
                raise ValueError(f"perturbation {name} must be a probability in [0, 1]")
        return self

    def rates(self) -> dict[str, float]:
        """Every kind's rate, by kind name."""
        extra = {k: float(v) for k, v in (self.model_extra or {}).items()}
        return {"slip": self.slip, "bump": self.bump, **extra}

    @property
    def active(self) -> bool:
        """Whether any event can fire."""
        return any(rate > 0 for rate in self.rates().values())


class PerturbEvent(FiniteFrozen):
    """A perturbation that fired during an execution."""

    kind: str = Field(description="The kind: slip (a held object dropped), bump (displaced)...")
    step: int = Field(ge=0, description="Index of the step it fired in (within its round).")
    object: str = Field(description="The object dropped or displaced.")
    shift: tuple[float, float] = Field(
        default=(0.0, 0.0), description="Bump: the horizontal displacement (m, world)."
    )
    at_s: float = Field(default=0.0, ge=0, description="Slip: flight time when it dropped (s).")


class LoopConfig(FiniteFrozen):
    """How a closed-loop episode replans."""

    max_rounds: int = Field(default=3, ge=1, le=20, description="Replans after round 0 (K).")
    step_budget: int | None = Field(
        default=None,
        ge=1,
        description="Steps executed over all rounds; None = 3 x the GT plan's steps.",
    )

    def budget(self, gt_steps: int) -> int:
        """The step budget of an episode whose GT plan has ``gt_steps`` steps."""
        return self.step_budget if self.step_budget is not None else 3 * max(1, gt_steps)


class ExecutedStep(FiniteFrozen):
    """One step the robot ran, as a replan's feedback states it."""

    step: PlanStep = Field(description="The step.")
    status: Literal["done", "failed"] = Field(description="How it ended.")
    code: str | None = Field(default=None, description="Failure code (failed steps).")
    detail: str | None = Field(default=None, description="One-line failure detail.")


class Feedback(FiniteFrozen):
    """What a replan's prompt tells the model about the rounds before it."""

    round: int = Field(ge=1, description="The replan's round (1 = first replan).")
    executed: tuple[ExecutedStep, ...] = Field(description="Steps run so far, every round.")
    held: str | None = Field(default=None, description="What the gripper holds now.")
    incomplete: bool = Field(
        default=False,
        description="Every step succeeded but the task is not complete (which goal is unmet "
        "is not said).",
    )
