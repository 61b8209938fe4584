"""Prompt configuration, rendered prompts and few-shot example scenes."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field, field_validator, model_validator

from vlm_bench.types.plan import ArmStep, PlanStep
from vlm_bench.types.task import InstructionVariant
from vlm_bench.types.world import SNAKE, Frozen

if TYPE_CHECKING:
    from vlm_bench.types.generation import GenerationRequest, RequestMeta

View = Literal["uav", "wrist", "overhead", "side"]
"""Camera names (the simulator's stable camera names, SPEC §2)."""

VIEWS: tuple[View, ...] = ("uav", "wrist", "overhead", "side")
"""All views, in the order the paper lists them (first-person first)."""


class PromptConfig(Frozen):
    """How prompts are built for a run; part of the run manifest."""

    k_shot: int = Field(default=2, ge=0, description="Few-shot examples in the system prompt.")
    few_shot_seed: int = Field(default=0, ge=0, description="Seed of the few-shot selection.")
    few_shot_selection: Literal["per_episode", "per_run"] = Field(
        default="per_episode",
        description="Draw examples per episode (seed + episode) or once per run (cacheable).",
    )
    views: tuple[View, ...] = Field(default=VIEWS, description="Camera views shown, in order.")
    object_list: bool = Field(default=True, description="List the scene's object ids.")
    instruction: InstructionVariant = Field(default="explicit", description="Instruction variant.")

    @field_validator("views")
    @classmethod
    def _unique_views(cls, views: tuple[View, ...]) -> tuple[View, ...]:
        if len(set(views)) != len(views):
            raise ValueError(f"views must be unique, got {list(views)}")
        return views


class TextPart(Frozen):
    """A span of prompt text."""

    type: Literal["text"] = "text"
    text: str


class ImageSlot(Frozen):
    """Where one camera view's image goes in the user turn."""

    type: Literal["image"] = "image"
    view: View


PromptPart = Annotated[TextPart | ImageSlot, Field(discriminator="type")]


class Prompt(Frozen):
    """A rendered prompt: system text, the user turn (text and image slots in order), images."""

    system: str = Field(description="System message: robot, views, skills, format, rules, shots.")
    user: tuple[PromptPart, ...] = Field(description="User turn: text parts and image slots.")
    prompt_hash: str = Field(description="sha256 of rendered text, templates and skill library.")
    example_ids: tuple[str, ...] = Field(default=(), description="Few-shot examples shown.")
    images: dict[str, bytes] = Field(
        default_factory=dict, exclude=True, repr=False, description="PNG bytes by view."
    )

    def views(self) -> list[View]:
        """Views whose images the user turn holds, in order."""
        return [p.view for p in self.user if isinstance(p, ImageSlot)]

    def to_request(
        self,
        request_id: str,
        *,
        episode_id: str = "",
        meta: RequestMeta | None = None,
        json_schema: dict[str, object] | None = None,
    ) -> GenerationRequest:
        """The backend request for this prompt: image slots filled with their PNG bytes."""
        from vlm_bench.types.generation import GenerationRequest, ImagePart

        parts: list[TextPart | ImagePart] = []
        for part in self.user:
            if isinstance(part, ImageSlot):
                parts.append(ImagePart(view=part.view, png=self.images[part.view]))
            else:
                parts.append(part)
        return GenerationRequest(
            id=request_id,
            episode_id=episode_id or request_id,
            system=self.system,
            user=tuple(parts),
            json_schema=json_schema,
            meta=meta,
        )


class FewShotExample(Frozen):
    """A hand-written example scene (never a benchmark task), shown as text in the prompt."""

    id: str = Field(pattern=SNAKE, description="Stable example id.")
    scene: str = Field(min_length=8, description="Where things are relative to the UAV, in words.")
    objects: tuple[str, ...] = Field(min_length=1, description="Object ids in the scene.")
    instruction: str = Field(min_length=8, description="The instruction given for the scene.")
    plan: tuple[PlanStep, ...] = Field(min_length=1, description="The correct plan.")

    @field_validator("plan", mode="before")
    @classmethod
    def _strip_subtask_numbers(cls, plan: object) -> object:
        # The file holds plans in the paper's format; subtask numbers must count from 0.
        if not isinstance(plan, list | tuple):
            return plan
        out: list[object] = []
        for i, step in enumerate(plan):
            if isinstance(step, dict) and "subtask" in step:
                if step["subtask"] != i:
                    raise ValueError(f"plan[{i}].subtask is {step['subtask']!r}, expected {i}")
                step = {k: v for k, v in step.items() if k != "subtask"}
            out.append(step)
        return out

    @model_validator(mode="after")
    def _plan_uses_listed_objects(self) -> FewShotExample:
        for obj in self.objects:
            if not re.match(SNAKE, obj):
                raise ValueError(f"object id {obj!r} is not snake_case")
        for i, step in enumerate(self.plan):
            if isinstance(step, ArmStep):
                for ref in (step.object, step.target):
                    if ref is not None and ref not in self.objects:
                        raise ValueError(f"plan[{i}] names {ref!r}, not in objects")
        return self


class FewShotLibrary(Frozen):
    """The file ``prompts/few_shot_examples.json``."""

    examples: tuple[FewShotExample, ...] = Field(min_length=1)
