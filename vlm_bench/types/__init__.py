"""Typed data models for everything that crosses a module boundary or is serialised."""

from vlm_bench.types.episode import Episode, EpisodeObject, Lighting, PartRef, UavPose
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import (
    HORIZONTAL_DIRECTIONS,
    ArmStep,
    Direction,
    PlanStep,
    UavStep,
    plan_to_json,
)
from vlm_bench.types.task import (
    INSTRUCTION_VARIANTS,
    ArmStepSpec,
    Goal,
    Instructions,
    InstructionVariant,
    PlacedObject,
    Suite,
    TaskSpec,
)
from vlm_bench.types.world import (
    EnvironmentSpec,
    LightSpec,
    ObjectKind,
    PartSpec,
    WorldCatalog,
)

__all__ = [
    "APPROACH",
    "HORIZONTAL_DIRECTIONS",
    "INSTRUCTION_VARIANTS",
    "ApproachGeometry",
    "ArmStep",
    "ArmStepSpec",
    "Direction",
    "EnvironmentSpec",
    "Episode",
    "EpisodeObject",
    "Goal",
    "InstructionVariant",
    "Instructions",
    "LightSpec",
    "Lighting",
    "ObjectKind",
    "PartRef",
    "PartSpec",
    "PlacedObject",
    "PlanStep",
    "Suite",
    "TaskSpec",
    "UavPose",
    "UavStep",
    "WorldCatalog",
    "plan_to_json",
]
