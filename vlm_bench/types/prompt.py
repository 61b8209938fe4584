"""Prompt configuration, rendered prompts and few-shot example scenes."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from vlm_bench.types.base import Frozen
from vlm_bench.types.generation import GenerationRequest, ImagePart, RequestMeta, TextPart
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.task import InstructionVariant
from vlm_bench.types.world import SNAKE

View = Literal["uav", "wrist", "overhead", "side"]
"""Camera names (the simulator's stable camera names, docs/design.md#world)."""

VIEWS: tuple[View, ...] = ("uav", "wrist", "overhead", "side")
"""All views, in the order the paper lists them (first-person first)."""


def _unique_views(views: tuple[View, ...]) -> tuple[View, ...]:
    if len(set(views)) != len(views):
        raise ValueError(f"views must be unique, got {list(views)}")
    return views


Views = Annotated[tuple[View, ...], AfterValidator(_unique_views)]
"""Camera views in order, each at most once."""


class PromptConfig(Frozen):
    """How prompts are built for a run; part of the run manifest."""

    k_shot: int = Field(default=2, ge=0, description="Few-shot examples in the system prompt.")
    few_shot_seed: int = Field(default=0, ge=0, description="Seed of the few-shot selection.")
    few_shot_selection: Literal["per_episode", "per_run"] = Field(
        default="per_episode",
        description="Draw examples per episode (seed + episode) or once per run (cacheable).",
    )
    views: Views = Field(default=VIEWS, description="Camera views shown, in order.")
    object_list: bool = Field(default=True, description="List the scene's object ids.")
    scene_as_text: bool = Field(
        default=False,
        description="Give every object's position in the UAV body frame as text (perfect "
        "perception).",
    )
    instruction: InstructionVariant = Field(default="explicit", description="Instruction variant.")


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
    object_order: tuple[str, ...] = Field(
        default=(), description="Object and part ids in the order the user turn lists them."
    )
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
        """The backend request for this prompt: image slots filled with their PNG bytes (left
        out where the views were not rendered, for a planner that reads no images)."""
        parts: list[TextPart | ImagePart] = []
        for part in self.user:
            if isinstance(part, ImageSlot):
                if self.images:
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


class ExampleObject(Frozen):
    """An object (or a drawer or knob of one) of a few-shot example scene, placed relative to
    the UAV: the scene text and the plan are derived from these numbers, never typed."""

    id: str = Field(pattern=SNAKE, description="Object or part id.")
    right: float = Field(description="Metres right of the UAV's centre (its centre/handle).")
    forward: float = Field(description="Metres ahead of the UAV's centre.")
    bottom: float = Field(ge=0, description="Height of its bottom (a part: its handle) (m).")
    tall: float = Field(default=0.0, ge=0, description="Its height (m); 0 for a part.")
    holds: Literal["on", "in"] = Field(
        default="on", description="Objects placed on it rest on its top, or in it on its floor."
    )
    part_of: str | None = Field(default=None, description="The object a drawer/knob belongs to.")
    part: Literal["drawer", "knob"] | None = Field(default=None, description="Part mechanism.")
    opening: float = Field(default=0.0, ge=0, description="How far a drawer is open (m).")
    pull: tuple[float, float] | None = Field(
        default=None, description="Direction (right, forward) a drawer pulls out."
    )

    @model_validator(mode="after")
    def _part_fields(self) -> ExampleObject:
        if (self.part is None) != (self.part_of is None):
            raise ValueError(f"{self.id}: give both part and part_of, or neither")
        if (self.part == "drawer") != (self.pull is not None):
            raise ValueError(f"{self.id}: a drawer, and only a drawer, needs pull")
        return self


class FewShotExample(Frozen):
    """A few-shot example scene (never a benchmark task): positions relative to the UAV and the
    ARM steps the instruction asks for. Its scene text and its UAV moves are derived by the
    prompt's rules (:func:`vlm_bench.prompting.examples.example_plan`)."""

    id: str = Field(pattern=SNAKE, description="Stable example id.")
    setting: str = Field(min_length=4, description="Where the scene is, in a few words.")
    uav_height: float = Field(gt=0, description="Height of the UAV's centre above the floor (m).")
    objects: tuple[ExampleObject, ...] = Field(min_length=1, description="The scene.")
    instruction: str = Field(min_length=8, description="The instruction given for the scene.")
    arm_steps: tuple[ArmStep, ...] = Field(min_length=1, description="The ARM steps it needs.")

    def object_ids(self) -> list[str]:
        """Ids of the scene's objects and parts."""
        return [o.id for o in self.objects]

    @model_validator(mode="after")
    def _steps_use_listed_objects(self) -> FewShotExample:
        ids = set(self.object_ids())
        if len(ids) != len(self.objects):
            raise ValueError("object ids must be unique")
        for i, step in enumerate(self.arm_steps):
            for ref in (step.object, step.target):
                if ref is not None and ref not in ids:
                    raise ValueError(f"arm_steps[{i}] names {ref!r}, not in objects")
        for obj in self.objects:
            if obj.part_of is not None and obj.part_of not in ids:
                raise ValueError(f"{obj.id}: part_of {obj.part_of!r} is not in objects")
        return self


class FewShotLibrary(Frozen):
    """The file ``prompts/few_shot_examples.json``."""

    examples: tuple[FewShotExample, ...] = Field(min_length=1)
