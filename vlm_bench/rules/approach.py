"""The UAV moves before an ARM step: reach, direction, stop, altitude, and their order.

The rule, as the prompt states it:

* a working point within ``reach_horizontal`` of the UAV (horizontally) needs no horizontal
  move; otherwise one move along the working point's bearing, quantised to the eight sectors,
  that stops at the working point's stand-off (or its closest approach);
* when the UAV's altitude differs from the working altitude (``operating_altitude``) by more
  than ``vertical_threshold``, one ``up`` or ``down`` move to it;
* ``up`` comes before the horizontal move and ``down`` after it, so the stowed arm is never
  lower than it has to be while the UAV flies level.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from vlm_bench.rules.frame import body_bearing_deg, move_stop, quantise_bearing
from vlm_bench.types.geometry import APPROACH, ApproachGeometry
from vlm_bench.types.plan import Direction

SECTOR_MARGIN_DEG = 8.0
"""deg: no move's bearing lies this close to a sector boundary (it could be either sector)."""
DECISION_MARGIN = 0.15
"""m: no working point lies this close to the reach limit (in reach or not could be either)."""
REACH_MARGIN = 0.06
"""m: a move leaves its working point at least this far inside reach."""
VERTICAL_MARGIN = 0.10
"""m: no altitude error lies this close to the vertical threshold."""


@dataclass(frozen=True)
class UavState:
    """UAV position (m) and heading (deg, CCW from the frame's +x) in some world frame."""

    x: float
    y: float
    z: float
    yaw_deg: float

    @property
    def xy(self) -> tuple[float, float]:
        """Horizontal position."""
        return self.x, self.y


@dataclass(frozen=True)
class WorkPoint:
    """Where an ARM step works (m, same frame as the UAV) and the horizontal stand-off at which
    a move towards it stops."""

    x: float
    y: float
    z: float
    standoff: float

    @property
    def xy(self) -> tuple[float, float]:
        """Horizontal position."""
        return self.x, self.y


@dataclass(frozen=True)
class Leg:
    """One UAV move: its direction and the UAV's state before and after it."""

    direction: Direction
    start: UavState
    end: UavState

    @property
    def vertical(self) -> bool:
        """True for ``up`` and ``down``."""
        return not self.direction.is_horizontal


def horizontal_distance(uav: UavState, point: WorkPoint) -> float:
    """Horizontal distance (m) from the UAV's centre to a working point."""
    return math.hypot(point.x - uav.x, point.y - uav.y)


def altitude_error(uav: UavState, point: WorkPoint, geo: ApproachGeometry = APPROACH) -> float:
    """Working altitude for ``point`` minus the UAV's altitude (m; > 0: the UAV must climb)."""
    return geo.operating_altitude(point.z) - uav.z


def _horizontal(uav: UavState, point: WorkPoint, geo: ApproachGeometry) -> Leg | None:
    if horizontal_distance(uav, point) <= geo.reach_horizontal:
        return None
    direction, _ = quantise_bearing(body_bearing_deg(uav.xy, uav.yaw_deg, point.xy))
    heading = uav.yaw_deg + direction.angle_deg
    x, y = move_stop(uav.xy, heading, point.xy, point.standoff, geo.max_move)
    return Leg(direction, uav, replace(uav, x=round(x, 4), y=round(y, 4)))


def approach_moves(uav: UavState, point: WorkPoint, geo: ApproachGeometry = APPROACH) -> list[Leg]:
    """The moves that bring ``point`` into the arm's reach at working altitude, in plan order."""
    dz = altitude_error(uav, point, geo)
    vertical = abs(dz) > geo.vertical_threshold
    target_z = round(geo.operating_altitude(point.z), 4)
    legs: list[Leg] = []
    if vertical and dz > 0:
        legs.append(Leg(Direction.UP, uav, replace(uav, z=target_z)))
        uav = legs[-1].end
    level = _horizontal(uav, point, geo)
    if level is not None:
        legs.append(level)
        uav = level.end
    if vertical and dz < 0:
        legs.append(Leg(Direction.DOWN, uav, replace(uav, z=target_z)))
    return legs


def ambiguity(uav: UavState, point: WorkPoint, geo: ApproachGeometry = APPROACH) -> str | None:
    """Why the moves for ``point`` hinge on a judgement the images cannot support, or None.

    Every decision of :func:`approach_moves` must be clear of its threshold: the altitude error
    by :data:`VERTICAL_MARGIN`, the horizontal distance by :data:`DECISION_MARGIN` and the
    bearing of a move by :data:`SECTOR_MARGIN_DEG`; and a move must end with the point
    :data:`REACH_MARGIN` inside reach. The GT builder resamples a seed where this is not None.
    """
    dz = altitude_error(uav, point, geo)
    if abs(abs(dz) - geo.vertical_threshold) < VERTICAL_MARGIN:
        return f"altitude difference {dz:+.2f} m is near the vertical threshold"
    dist = horizontal_distance(uav, point)
    if abs(dist - geo.reach_horizontal) < DECISION_MARGIN:
        return f"working point {dist:.2f} m away lies at the edge of reach"
    if dist <= geo.reach_horizontal:
        return None
    bearing = body_bearing_deg(uav.xy, uav.yaw_deg, point.xy)
    direction, margin = quantise_bearing(bearing)
    if margin < SECTOR_MARGIN_DEG:
        return f"bearing {bearing:.1f} deg is near a sector boundary"
    heading = uav.yaw_deg + direction.angle_deg
    stop = move_stop(uav.xy, heading, point.xy, point.standoff, geo.max_move)
    if math.dist(stop, point.xy) > geo.reach_horizontal - REACH_MARGIN:
        return "the move cannot bring the working point into reach"
    return None
