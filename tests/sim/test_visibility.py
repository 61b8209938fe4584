"""Whether the first target is in the ``uav`` camera's view: the analytic camera matches the
compiled model's, hand-made poses give the expected answers, and the answer agrees with a
segmentation render of the ``uav`` view."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import get_episode
from vlm_bench.sim.constants import CAM_UAV, part_handle_site
from vlm_bench.sim.footprint import pixel_mask
from vlm_bench.sim.labels import project_points
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.sim.visibility import (
    first_target,
    first_target_visible,
    reference_point,
    uav_camera_pose,
)
from vlm_bench.types.episode import Episode, UavPose

SIZE = 448
SAMPLE = [(task.id, k % 10) for k, task in enumerate(all_tasks())][::4]  # 15 tasks, mixed seeds


def _facing(episode: Episode, yaw_offset_deg: float, distance: float = 1.0) -> Episode:
    """The episode with the UAV ``distance`` m from its first target and as high above it, on
    the room's side (a part: in front of its fixture), heading at it turned by
    ``yaw_offset_deg``: the target is 45° down, 10° below the image centre."""
    ref = first_target(episode)
    assert ref is not None
    target = reference_point(episode, ref)
    parents = {p.id: p.parent for p in episode.parts}
    if ref in parents:
        yaw = math.radians(next(o.yaw_deg for o in episode.objects if o.id == parents[ref]))
        side = np.array([math.cos(yaw), math.sin(yaw)])
    elif np.linalg.norm(target[:2]) > 0.1:
        side = -target[:2] / np.linalg.norm(target[:2])
    else:
        side = np.array([-1.0, 0.0])
    pos = target + np.array([*(distance * side), distance])
    heading = math.degrees(math.atan2(-side[1], -side[0])) + yaw_offset_deg
    start = UavPose(pos=(float(pos[0]), float(pos[1]), float(pos[2])), yaw_deg=heading)
    return episode.model_copy(update={"uav_start": start})


def _target_pixels(scene: Scene, renderer: SnapshotRenderer) -> int:
    ref = first_target(scene.episode)
    assert ref is not None
    body = ref
    if ref in {p.id for p in scene.episode.parts}:
        site = scene.model.site(part_handle_site(ref)).id
        body = scene.model.body(scene.model.site_bodyid[site]).name
    seg = renderer.render_segmentation(scene.model, scene.data, CAM_UAV, SIZE)
    return int(pixel_mask(seg, subtree_geoms(scene.model, body)).sum())


@pytest.mark.parametrize(("task", "seed"), SAMPLE)
def test_analytic_uav_camera_is_the_models(task: str, seed: int) -> None:
    episode = get_episode(task, seed)
    scene = build_scene(episode)
    cam = scene.model.camera(CAM_UAV).id
    pos, rot = uav_camera_pose(episode.uav_start)
    np.testing.assert_allclose(pos, scene.data.cam_xpos[cam], atol=1e-12)
    np.testing.assert_allclose(rot, scene.data.cam_xmat[cam].reshape(3, 3), atol=1e-12)
    ref = first_target(episode)
    assert ref is not None
    _, inside = project_points(
        scene.model, scene.data, CAM_UAV, reference_point(episode, ref)[None, :], SIZE, SIZE
    )
    assert bool(inside[0]) == first_target_visible(episode)


@pytest.mark.parametrize("task", ["standard_pick_place", "drawer_interaction"])
def test_hand_made_poses(task: str) -> None:
    episode = get_episode(task, 0)
    assert first_target_visible(_facing(episode, 0.0))
    assert first_target_visible(_facing(episode, 25.0))
    assert not first_target_visible(_facing(episode, 60.0))  # off the image's side
    assert not first_target_visible(_facing(episode, 180.0))  # behind the camera
    below = _facing(episode, 0.0, distance=0.2)  # nearly straight down: under the image
    assert not first_target_visible(below)


def test_no_arm_step_is_not_visible() -> None:
    episode = get_episode("standard_pick_place", 0)
    bare = episode.model_copy(update={"gt_plan": episode.uav_steps()})
    assert not first_target_visible(bare)


@pytest.mark.parametrize(("task", "seed"), SAMPLE)
def test_visible_targets_show_up_in_the_uav_view(
    task: str, seed: int, renderer: SnapshotRenderer
) -> None:
    """Visible (the reference point projects inside) ⇒ the target's pixels are in the render;
    and the turned-around UAV sees none of it."""
    episode = get_episode(task, seed)
    facing = _facing(episode, 0.0)
    assert first_target_visible(facing)
    assert _target_pixels(build_scene(facing), renderer) > 0
    away = _facing(episode, 180.0)
    assert not first_target_visible(away)
    assert _target_pixels(build_scene(away), renderer) == 0
    scene = build_scene(episode)
    if first_target_visible(episode):
        assert _target_pixels(scene, renderer) > 0


def test_yaw_sweep_matches_the_render(renderer: SnapshotRenderer) -> None:
    """Turning the UAV in place: where the function says not visible, at most the target's edge
    shows (its centre is outside); where visible, it shows."""
    episode = get_episode("standard_pick_place", 0)
    for yaw in range(-90, 91, 15):
        turned = _facing(episode, float(yaw))
        pixels = _target_pixels(build_scene(turned), renderer)
        if first_target_visible(turned):
            assert pixels > 0, yaw
        elif abs(yaw) >= 60:
            assert pixels == 0, yaw
