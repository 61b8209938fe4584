"""Whether a point is in the ``uav`` camera's view at an episode's start, computed analytically.

The camera's pose follows from the UAV's start pose and the mount constants in
:mod:`vlm_bench.sim.uav` exactly as the compiled model places it (the tests compare both), so no
scene has to be built: a check costs microseconds. Occlusion is not considered.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.errors import UnknownNameError
from vlm_bench.sim.uav import CAMERA_FOVY, CAMERA_PITCH_DEG, CAMERA_POS
from vlm_bench.types.base import FloatArray as Vec
from vlm_bench.types.episode import Episode, UavPose


def uav_camera_pose(start: UavPose) -> tuple[Vec, Vec]:
    """World position and orientation of the ``uav`` camera with the UAV at ``start``.

    Returns:
        ``(pos, rot)``: the camera's position (3,) and a (3, 3) matrix whose columns are the
        camera's x (image right), y (image up) and z (backwards) axes in the world, as MuJoCo's
        ``cam_xpos`` / ``cam_xmat``.
    """
    yaw, pitch = math.radians(start.yaw_deg), math.radians(CAMERA_PITCH_DEG)
    turn = np.array(
        [[math.cos(yaw), -math.sin(yaw), 0.0], [math.sin(yaw), math.cos(yaw), 0.0], [0, 0, 1.0]]
    )
    right = np.array([0.0, -1.0, 0.0])  # same xyaxes as the camera in uav.add_uav
    up = np.array([math.sin(pitch), 0.0, math.cos(pitch)])
    local = np.column_stack([right, up, np.cross(right, up)])
    pos: Vec = np.asarray(start.pos, dtype=np.float64) + turn @ np.asarray(CAMERA_POS)
    rot: Vec = turn @ local
    return pos, rot


def in_uav_view(start: UavPose, points: NDArray[np.floating]) -> NDArray[np.bool_]:
    """Which world points (N, 3) lie in front of the ``uav`` camera and inside its square image."""
    pos, rot = uav_camera_pose(start)
    local = (np.asarray(points, dtype=np.float64).reshape(-1, 3) - pos) @ rot
    depth = -local[:, 2]
    limit = math.tan(math.radians(CAMERA_FOVY / 2)) * np.maximum(depth, 0.0)
    inside: NDArray[np.bool_] = (
        (depth > 0) & (np.abs(local[:, 0]) < limit) & (np.abs(local[:, 1]) < limit)
    )
    return inside


def reference_point(episode: Episode, ref: str) -> Vec:
    """The point that stands for an object or part: an object's centre, a part's handle."""
    for obj in episode.objects:
        if obj.id == ref:
            height = object_kind(obj.kind).size[2]
            centre: Vec = np.asarray(obj.pos, dtype=np.float64) + np.array([0.0, 0.0, height / 2])
            return centre
    for part in episode.parts:
        if part.id == ref:
            return np.asarray(part.handle, dtype=np.float64)
    raise UnknownNameError("object or part", ref, episode.object_ids())


def first_target(episode: Episode) -> str | None:
    """Id of the object or part the plan's first ARM step acts on (None without ARM steps)."""
    steps = episode.arm_steps()
    return steps[0].object if steps else None


def first_target_visible(episode: Episode) -> bool:
    """Whether the first ARM step's object projects into the ``uav`` image at the start.

    The object's reference point (:func:`reference_point`) must lie in front of the camera and
    inside the image; occlusion is not checked. False when the plan has no ARM step.
    """
    ref = first_target(episode)
    if ref is None:
        return False
    return bool(in_uav_view(episode.uav_start, reference_point(episode, ref)[None, :])[0])
