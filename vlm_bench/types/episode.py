"""Episodes: a task materialised for one seed (layout, UAV start, GT plan, goals)."""

from __future__ import annotations

from pydantic import Field

from vlm_bench.types.base import Frozen, Vec3
from vlm_bench.types.plan import ArmStep, PlanStep, UavStep
from vlm_bench.types.task import Goal, Instructions, InstructionVariant, Role, Suite


class EpisodeObject(Frozen):
    """An object placed in the episode's scene."""

    id: str = Field(description="Object id used in plans.")
    kind: str = Field(description="Object kind from the world catalogue.")
    color: str = Field(description="Named colour.")
    pos: Vec3 = Field(description="World position of the object's bottom centre (m).")
    yaw_deg: float = Field(description="Heading (deg); the object's +x is its front.")
    on: str = Field(description="Id of the object it rests on, or 'floor'.")
    role: Role
    initial: dict[str, float] = Field(default_factory=dict, description="Initial part states.")
    label: str | None = Field(
        default=None, description="Set-of-marks label drawn in third-person views, if any."
    )


class PartRef(Frozen):
    """An addressable part (drawer, knob) and the object it belongs to."""

    id: str = Field(description="Part id used in plans, e.g. top_drawer.")
    parent: str = Field(description="Id of the object that carries the part.")
    kind: str = Field(description="Part mechanism: drawer or knob.")
    handle: Vec3 = Field(description="World position of its handle/knob at the start (m).")


class UavPose(Frozen):
    """UAV body pose: position (m) and heading (deg, CCW from world +x)."""

    pos: Vec3
    yaw_deg: float


class Lighting(Frozen):
    """Per-episode lighting jitter applied on top of the environment's light."""

    azimuth_deg: float = Field(description="Rotation of the key light about z (deg).")
    intensity: float = Field(description="Multiplier of the key light's diffuse intensity.")


class CameraPose(Frozen):
    """A fixed third-person camera: where it stands, where it looks and how wide."""

    pos: Vec3 = Field(description="Position (m, world).")
    forward: Vec3 = Field(description="Viewing direction (world).")
    fovy: float = Field(gt=0.0, lt=180.0, description="Vertical field of view (deg).")


class Episode(Frozen):
    """Task × seed: everything needed to build the scene, prompt the model and score a plan."""

    task_id: str
    seed: int = Field(ge=0)
    suite: Suite
    environment: str
    instructions: Instructions
    objects: tuple[EpisodeObject, ...]
    parts: tuple[PartRef, ...] = ()
    uav_start: UavPose
    lighting: Lighting
    gt_plan: tuple[PlanStep, ...]
    gt_uav_poses: tuple[UavPose, ...] = Field(
        description="Expected UAV pose after each GT step (ideal kinematics)."
    )
    goals: tuple[Goal, ...]
    object_px: dict[str, dict[str, float]] = Field(
        default_factory=dict,
        description="Task object id -> third-person view -> its size there at 448² (px), "
        "projected from the geometry (vlm_bench.sim.view_sizes); empty in older files.",
    )
    cameras: dict[str, CameraPose] = Field(
        default_factory=dict,
        description="Third-person view (overhead, side) -> the camera it is shown from, as the "
        "generator chose it (vlm_bench.sim.height_views); empty in older files, where the scene "
        "builder chooses it again.",
    )

    def instruction(self, variant: InstructionVariant) -> str:
        """The instruction text of one variant."""
        return getattr(self.instructions, variant)  # type: ignore[no-any-return]

    def object_ids(self) -> list[str]:
        """Ids a plan may reference: objects and parts, in scene order."""
        return [o.id for o in self.objects] + [p.id for p in self.parts]

    def uav_steps(self) -> list[UavStep]:
        """The GT plan's UAV steps."""
        return [s for s in self.gt_plan if isinstance(s, UavStep)]

    def arm_steps(self) -> list[ArmStep]:
        """The GT plan's ARM steps."""
        return [s for s in self.gt_plan if isinstance(s, ArmStep)]
