"""Geometric facts shared by the episode generator (GT derivation) and the simulator/executor.

They live here, below both, so the ground truth and the executor cannot disagree on where the
arm base is, how far it reaches, or where the UAV stops.
"""

from __future__ import annotations

import math

from pydantic import Field

from vlm_bench.types.base import Frozen

UAV_ARM_LENGTH = 0.33
"""m: from the UAV's centre to each of its four motor axes (quad-X, arms at ±45° and ±135°)."""
UAV_ROTOR_RADIUS = 0.17
"""m: radius of each rotor disc."""
UAV_ROTOR_SPAN = round(2 * (UAV_ARM_LENGTH + UAV_ROTOR_RADIUS), 2)
"""m: the UAV across, from rotor tip to rotor tip along a diagonal (the prompt's ruler)."""


class ApproachGeometry(Frozen):
    """How the UAV approaches an object and when an object counts as in reach."""

    arm_base_below_uav: float = Field(
        default=0.10, description="Arm base (Panda link0) below the UAV body origin (m)."
    )
    op_height: float = Field(
        default=0.60, description="Arm base height above an object's reference point (m)."
    )
    ideal_standoff: float = Field(
        default=0.65, description="Ideal arm-base-to-object distance (m), official evaluator."
    )
    standoff_min: float = Field(default=0.50, description="S_pos feasible range lower bound (m).")
    standoff_max: float = Field(default=0.80, description="S_pos feasible range upper bound (m).")
    reach: float = Field(
        default=0.85, description="Arm-base-to-object distance (m) beyond which a move is needed."
    )
    vertical_threshold: float = Field(
        default=0.20, description="Altitude error (m) beyond which an up/down move is needed."
    )
    stow_depth: float = Field(
        default=0.50, description="Lowest point of the stowed arm below the UAV origin (m)."
    )
    stow_radius: float = Field(
        default=0.40, description="Horizontal reach of the stowed arm from the UAV axis (m)."
    )
    stow_clearance: float = Field(
        default=0.02, description="Vertical clearance the stowed arm keeps above objects (m)."
    )
    default_move: float = Field(default=1.0, description="Move length with no ARM step after (m).")
    max_move: float = Field(default=4.0, description="Longest single move (m).")

    @property
    def standoff_horizontal(self) -> float:
        """Horizontal UAV-to-object distance at the ideal stand-off and operating altitude."""
        return math.sqrt(self.ideal_standoff**2 - self.op_height**2)

    @property
    def reach_horizontal(self) -> float:
        """Horizontal distance within which an object at operating altitude is in reach."""
        return math.sqrt(self.reach**2 - self.op_height**2)

    def operating_altitude(self, ref_z: float) -> float:
        """UAV body altitude for working on a reference point at height ``ref_z``."""
        return ref_z + self.op_height + self.arm_base_below_uav


APPROACH = ApproachGeometry()
