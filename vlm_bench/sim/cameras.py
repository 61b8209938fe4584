"""Fixed third-person cameras (``overhead``, ``side``) framed on each episode's work area."""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world import environment, object_kind
from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_SIDE
from vlm_bench.types.episode import Episode

OVERHEAD_FOVY = 60.0
SIDE_FOVY = 55.0
SIDE_ELEVATION_DEG = 28.0


def look_at_xyaxes(pos: NDArray[np.float64], target: NDArray[np.float64]) -> list[float]:
    """MuJoCo ``xyaxes`` for a camera at ``pos`` looking at ``target`` with world z up."""
    forward = target - pos
    forward /= np.linalg.norm(forward)
    up_hint = np.array([0.0, 0.0, 1.0])
    if abs(float(forward @ up_hint)) > 0.999:  # looking straight down: pick +y as image up
        up_hint = np.array([0.0, 1.0, 0.0])
    right = np.cross(forward, up_hint)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return [*right.tolist(), *up.tolist()]


def framing_points(episode: Episode) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points the third-person views must show, with a margin radius each (m).

    The plan's objects and parts, every movable object, and the UAV start (its rotors reach
    0.55 m from its centre).
    """
    referenced = {s.object for s in episode.arm_steps()} | {
        s.target for s in episode.arm_steps() if s.target
    }
    points, margins = [np.array(episode.uav_start.pos)], [0.6]
    for obj in episode.objects:
        kind = object_kind(obj.kind)
        if obj.id in referenced or (kind.movable and obj.role != "support"):
            points.append(np.array(obj.pos) + np.array([0.0, 0.0, kind.size[2] / 2]))
            margins.append(0.5 * max(kind.size[:2]) + 0.1)
    for part in episode.parts:
        if part.id in referenced:
            points.append(np.array(part.handle))
            margins.append(0.25)
    return np.stack(points), np.array(margins)


def fits(
    pos: NDArray[np.float64],
    target: NDArray[np.float64],
    fovy: float,
    points: NDArray[np.float64],
    margins: NDArray[np.float64],
    fill: float = 0.92,
) -> bool:
    """True when every point, grown by its margin, projects inside ``fill`` of a square frame."""
    axes = np.array(look_at_xyaxes(pos, target)).reshape(2, 3)
    forward = np.cross(axes[0], axes[1])
    vec = points - pos
    depth = vec @ -forward
    if (depth <= margins).any():
        return False
    limit = math.tan(math.radians(fovy / 2)) * fill
    return bool(((np.abs(vec @ axes.T) + margins[:, None]) / depth[:, None] <= limit).all())


def _side_azimuth(episode: Episode, center: NDArray[np.float64]) -> float:
    """Look at articulated fixtures from their front-side; else from the -y side of the area."""
    for obj in episode.objects:
        if object_kind(obj.kind).parts:
            return obj.yaw_deg + 50.0
    return -90.0 + 20.0


def add_third_person_cameras(spec: mujoco.MjSpec, episode: Episode) -> None:
    """Add ``overhead`` and ``side`` cameras framing the episode's work area."""
    points, margins = framing_points(episode)
    lo, hi = points.min(axis=0), points.max(axis=0)
    center = (lo + hi) / 2
    center[2] = float(np.median(points[1:, 2])) if len(points) > 1 else 0.75
    half_room = environment(episode.environment).room_half_size - 0.3
    # Overhead: high above the area, tilted a little so heights read; raised until all fits.
    height = 1.5
    while True:
        pos = np.array([center[0], center[1] - 0.2 * height, center[2] + height])
        if height > 12 or fits(pos, center, OVERHEAD_FOVY, points, margins):
            break
        height += 0.1
    spec.worldbody.add_camera(
        name=CAM_OVERHEAD,
        pos=pos.tolist(),
        xyaxes=look_at_xyaxes(pos, center),
        fovy=OVERHEAD_FOVY,
    )
    # Side: from the side at a moderate elevation, backed off until all fits, inside the room.
    az = math.radians(_side_azimuth(episode, center))
    elev = math.radians(SIDE_ELEVATION_DEG)
    offset = np.array(
        [math.cos(az) * math.cos(elev), math.sin(az) * math.cos(elev), math.sin(elev)]
    )
    dist = 1.5
    while True:
        pos = center + dist * offset
        if dist > 12 or fits(pos, center, SIDE_FOVY, points, margins):
            break
        dist += 0.1
    pos[:2] = np.clip(pos[:2], -half_room, half_room)
    spec.worldbody.add_camera(
        name=CAM_SIDE, pos=pos.tolist(), xyaxes=look_at_xyaxes(pos, center), fovy=SIDE_FOVY
    )
