"""Working points: where an ARM step works, where a placed object comes to rest, and how the
scene changes after a skill. The numbers the prompt states come from here (:func:`rule_numbers`).
"""

from __future__ import annotations

from functools import cache

from pydantic import Field

from vlm_bench.catalog.world_catalog import object_kinds
from vlm_bench.types.base import Frozen
from vlm_bench.types.geometry import APPROACH, UAV_ROTOR_SPAN, ApproachGeometry

CONTAINER_FLOOR = 0.012
"""m: a container's inner floor above its base; what is placed in it rests there."""
DRAWER_PULL = 0.35
"""m: how far open a drawer is after ``pull`` (the executor requires at least this)."""
DRAWER_FLOOR_BELOW_HANDLE = 0.10
"""m: a drawer's floor below its handle; what is placed in it rests there."""
DRAWER_INSIDE_BEHIND_HANDLE = 0.20
"""m: the middle of a drawer's floor behind its handle (towards the cabinet)."""


def rest_height(bottom_z: float, tall: float, *, container: bool, support: bool) -> float:
    """Height (m) at which an object placed on or in another rests: an open container's floor,
    else the top (a support's surface, or the top of an object to stack on)."""
    if container and not support:
        return bottom_z + CONTAINER_FLOOR
    return bottom_z + tall


def drawer_standoffs() -> tuple[float, ...]:
    """Distinct horizontal stand-offs (m) of drawer handles in the world catalogue."""
    return tuple(
        sorted(
            {
                p.standoff
                for k in object_kinds().values()
                for p in k.parts
                if p.kind == "drawer" and p.standoff is not None
            }
        )
    )


class RuleNumbers(Frozen):
    """Every number the prompt states about UAV moves, from the geometry the GT uses."""

    reach_horizontal: float = Field(description="Horizontal reach from the UAV's centre (m).")
    arm_reach: float = Field(description="Arm-base-to-point distance that reach stands for (m).")
    standoff: float = Field(description="Horizontal stand-off where a move stops (m).")
    drawer_standoff: float = Field(description="Stand-off for a drawer's handle or inside (m).")
    working_height: float = Field(description="UAV centre above the working point (m).")
    vertical_threshold: float = Field(description="Altitude error that needs up/down (m).")
    sector_deg: float = Field(description="Width of each direction sector (deg).")
    drawer_pull: float = Field(description="How far a pulled drawer opens (m).")
    max_move: float = Field(description="Longest single move (m).")
    rotor_span: float = Field(description="The UAV across, rotor tip to rotor tip (m).")
    container_floor: float = Field(description="A container's floor above its base (m).")
    drawer_floor_below_handle: float = Field(description="A drawer's floor below its handle (m).")
    drawer_inside_behind_handle: float = Field(
        description="The middle of a drawer's floor behind its handle (m)."
    )


@cache
def rule_numbers(geo: ApproachGeometry = APPROACH) -> RuleNumbers:
    """The prompt's numbers, computed from ``geo`` and the world catalogue."""
    from vlm_bench.rules.frame import SECTOR_DEG

    drawers = drawer_standoffs()
    return RuleNumbers(
        reach_horizontal=round(geo.reach_horizontal, 2),
        arm_reach=geo.reach,
        standoff=round(geo.standoff_horizontal, 2),
        drawer_standoff=drawers[0] if len(drawers) == 1 else round(geo.standoff_horizontal, 2),
        working_height=round(geo.op_height + geo.arm_base_below_uav, 2),
        vertical_threshold=geo.vertical_threshold,
        sector_deg=SECTOR_DEG,
        drawer_pull=DRAWER_PULL,
        max_move=geo.max_move,
        rotor_span=UAV_ROTOR_SPAN,
        container_floor=CONTAINER_FLOOR,
        drawer_floor_below_handle=DRAWER_FLOOR_BELOW_HANDLE,
        drawer_inside_behind_handle=DRAWER_INSIDE_BEHIND_HANDLE,
    )
