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


def work_area(episode: Episode) -> tuple[NDArray[np.float64], float]:
    """Centre (x, y, z) and horizontal radius covering the plan's objects and the UAV start."""
    referenced = {s.object for s in episode.arm_steps()} | {
        s.target for s in episode.arm_steps() if s.target
    }
    points = [np.array(episode.uav_start.pos)]
    for obj in episode.objects:
        kind = object_kind(obj.kind)
        if obj.id in referenced or (kind.movable and obj.role != "support"):
            points.append(np.array(obj.pos) + [0.0, 0.0, kind.size[2] / 2])
    points.extend(np.array(p.handle) for p in episode.parts if p.id in referenced)
    pts = np.stack(points)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    center = (lo + hi) / 2
    center[2] = float(np.median(pts[1:, 2])) if len(pts) > 1 else 0.75
    radius = float(np.linalg.norm((hi - lo)[:2]) / 2)
    return center, radius


def _side_azimuth(episode: Episode, center: NDArray[np.float64]) -> float:
    """Look at articulated fixtures from their front-side; else from the -y side of the area."""
    for obj in episode.objects:
        if object_kind(obj.kind).parts:
            return obj.yaw_deg + 50.0
    return -90.0 + 20.0


def add_third_person_cameras(spec: mujoco.MjSpec, episode: Episode) -> None:
    """Add ``overhead`` and ``side`` cameras framing the episode's work area."""
    center, radius = work_area(episode)
    half_room = environment(episode.environment).room_half_size - 0.3
    # Overhead: high above the area, tilted a little so heights read.
    height = max(2.6, (radius + 0.6) / math.tan(math.radians(OVERHEAD_FOVY / 2))) + center[2]
    pos = np.array([center[0], center[1] - 0.35 * (height - center[2]), height])
    spec.worldbody.add_camera(
        name=CAM_OVERHEAD, pos=pos.tolist(), xyaxes=look_at_xyaxes(pos, center),
        fovy=OVERHEAD_FOVY,
    )
    # Side: from the side at a moderate elevation, kept inside the room.
    az = math.radians(_side_azimuth(episode, center))
    dist = max(2.4, (radius + 0.7) / math.tan(math.radians(SIDE_FOVY / 2)))
    elev = math.radians(SIDE_ELEVATION_DEG)
    offset = np.array([math.cos(az) * math.cos(elev), math.sin(az) * math.cos(elev), math.sin(elev)])
    pos = center + dist * offset
    pos[:2] = np.clip(pos[:2], -half_room, half_room)
    spec.worldbody.add_camera(
        name=CAM_SIDE, pos=pos.tolist(), xyaxes=look_at_xyaxes(pos, center), fovy=SIDE_FOVY
    )
