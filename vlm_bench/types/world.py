"""The world catalogue (``ground_truth/world.json``): colours, object kinds, environments."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from vlm_bench.types.base import RGBA, Frozen, Vec3

SNAKE = r"^[a-z][a-z0-9_]*$"


class PartSpec(Frozen):
    """An addressable part of an articulated object (a drawer, a knob)."""

    name: str = Field(
        pattern=SNAKE, description="Object id the part has in plans, e.g. top_drawer."
    )
    kind: Literal["drawer", "knob"] = Field(description="Mechanism type of the part.")
    handle: Vec3 = Field(
        description="Handle/knob position in the object's frame (m, origin at base)."
    )
    standoff: float | None = Field(
        default=None, description="Horizontal UAV stand-off for this part (m); None = default."
    )
    approach_front: bool = Field(
        default=True, description="The part must be approached from the object's front (+x)."
    )


class ObjectKind(Frozen):
    """A kind of object a builder can make; geometry facts the episode generator needs."""

    name: str = Field(pattern=SNAKE, description="Kind name used in task files, e.g. basket.")
    category: str = Field(description="Asset category as in the paper's asset table.")
    description: str = Field(description="What it looks like, one line.")
    size: Vec3 = Field(description="Bounding box (x, y, z) in m at yaw 0; origin at bottom centre.")
    mass: float = Field(gt=0, description="Mass in kg (movable objects).")
    movable: bool = Field(description="Free-floating rigid body (False: fixed furniture).")
    graspable: bool = Field(description="The Panda gripper can pick it up.")
    container: bool = Field(default=False, description="Other objects can be placed inside it.")
    support: bool = Field(default=False, description="Other objects can be placed on top of it.")
    parts: tuple[PartSpec, ...] = Field(default=(), description="Articulated parts, if any.")
    default_color: str | None = Field(default=None, description="Colour used when none is given.")


class LightSpec(Frozen):
    """Key light of an environment."""

    direction: Vec3 = Field(description="Direction the directional light points to.")
    diffuse: float = Field(ge=0, le=2, description="Diffuse intensity (grey level).")
    ambient: float = Field(ge=0, le=1, description="Ambient intensity (grey level).")


class EnvironmentSpec(Frozen):
    """One of the environment variants (household, industrial, outdoor)."""

    name: str = Field(pattern=SNAKE, description="Variant name used in task files.")
    type: Literal["household", "industrial", "outdoor"] = Field(description="Environment type.")
    description: str = Field(description="One line, for humans and prompts.")
    floor_color: str = Field(description="Named colour of the floor / ground.")
    floor_texture: Literal["checker", "grid", "flat", "noise"] = Field(description="Floor pattern.")
    floor_color2: str = Field(description="Second colour of the floor pattern.")
    walls: bool = Field(description="Enclosed by walls (indoor) or open to the sky (outdoor).")
    wall_color: str = Field(description="Named colour of the walls (if any).")
    sky_top: RGBA = Field(description="Skybox gradient top colour.")
    sky_bottom: RGBA = Field(description="Skybox gradient bottom colour.")
    room_half_size: float = Field(gt=2, description="Half the side of the square arena (m).")
    light: LightSpec


class WorldCatalog(Frozen):
    """Everything a task file may name: colours, object kinds, environments."""

    colors: dict[str, RGBA] = Field(description="Named colours used by objects and materials.")
    object_kinds: tuple[ObjectKind, ...]
    environments: tuple[EnvironmentSpec, ...]
