"""Third-person framing: the closest fit is exact and tight; the cameras keep their orientation
and hold the UAV start and every framed object in view, in every task."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.catalog.world_catalog import environment
from vlm_bench.episodes import get_episode
from vlm_bench.sim.cameras import WALL_CLEARANCE, framing_points
from vlm_bench.sim.constants import CAM_OVERHEAD, THIRD_PERSON_CAMERAS
from vlm_bench.sim.framing import closest_fit, fits, occluded, segment_hits_boxes, view_xyaxes
from vlm_bench.sim.labels import project_points
from vlm_bench.sim.scene import Scene, build_scene

SIZE = 448
coords = st.floats(-3.0, 3.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(
    points=arrays(np.float64, (5, 3), elements=coords),
    margins=arrays(np.float64, 5, elements=st.floats(0.0, 0.6)),
    azimuth=st.floats(-math.pi, math.pi),
    elevation=st.floats(0.2, 1.55),
    fovy=st.floats(15.0, 90.0),
)
def test_closest_fit_sees_everything_and_cannot_come_closer(
    points: np.ndarray, margins: np.ndarray, azimuth: float, elevation: float, fovy: float
) -> None:
    forward = -np.array(
        [
            math.cos(azimuth) * math.cos(elevation),
            math.sin(azimuth) * math.cos(elevation),
            math.sin(elevation),
        ]
    )
    pos = closest_fit(forward, fovy, points, margins)
    assert fits(pos, forward, fovy, points, margins)
    assert not fits(pos + 0.01 * forward, forward, fovy, points, margins)


@settings(max_examples=200, deadline=None)
@given(forward=arrays(np.float64, 3, elements=coords).filter(lambda v: np.linalg.norm(v) > 1e-3))
def test_view_axes_are_orthonormal_image_up_highest_and_cached_unchanged(
    forward: np.ndarray,
) -> None:
    first = view_xyaxes(forward)
    right, up = np.array(first[:3]), np.array(first[3:])
    unit = forward / np.linalg.norm(forward)
    np.testing.assert_allclose([right @ right, up @ up, right @ up], [1.0, 1.0, 0.0], atol=1e-9)
    np.testing.assert_allclose([right @ unit, up @ unit], [0.0, 0.0], atol=1e-9)
    if abs(unit[2]) < 0.999:  # image right level, image up towards world +z
        assert abs(right[2]) < 1e-9 and up[2] >= 0.0
    first[0] += 1.0  # a caller changing its copy does not change what the cache answers
    assert view_xyaxes(forward.copy()) == [right[0], *first[1:]]


def test_fit_matches_the_rendered_projection() -> None:
    """A point on the fitted frustum's edge projects onto the image border."""
    forward = np.array([0.0, 0.3, -1.0])
    points = np.array([[-1.0, 0.0, 0.0], [1.5, 0.5, 0.7], [0.2, 1.2, 0.3]])
    pos = closest_fit(forward, 40.0, points, np.zeros(3))
    right, up = np.array(view_xyaxes(forward)).reshape(2, 3)
    rel = points - pos
    depth = rel @ (forward / np.linalg.norm(forward))
    half = SIZE / 2 / math.tan(math.radians(20.0))
    u = SIZE / 2 + half * (rel @ right) / depth
    v = SIZE / 2 - half * (rel @ up) / depth
    edges = np.concatenate([u, v])
    assert np.isclose(edges, 0.0, atol=1e-6).any() or np.isclose(edges, SIZE, atol=1e-6).any()
    assert ((u > -1e-6) & (u < SIZE + 1e-6) & (v > -1e-6) & (v < SIZE + 1e-6)).all()


def test_occluded_counts_only_nearer_overlapping_blockers() -> None:
    pos = np.zeros(3)
    points = np.array([[0.0, 5.0, 0.0], [0.0, 1.0, 0.0], [3.0, 5.0, 0.0]])
    blockers = np.array([[0.0, 2.0, 0.0]])
    hidden = occluded(pos, points, np.full(3, 0.1), blockers, np.array([0.3]))
    assert hidden.tolist() == [1.0, 0.0, 0.0]


def test_segment_hits_boxes_sees_only_boxes_in_between() -> None:
    start = np.array([0.0, -3.0, 0.5])
    centre, half = np.array([0.0, 0.0, 0.1]), np.array([0.3, 0.05, 0.1])
    ends = np.array(
        [
            [0.0, 1.0, 0.0],  # behind the box, low: blocked
            [0.0, 1.0, 1.0],  # behind it, high: the line passes above
            [0.0, -1.0, 0.0],  # in front of it
            [0.0, 0.0, 0.1],  # inside it: the end itself does not count, the way in does
            [0.6, 1.0, 0.0],  # beside it
            [0.2, 1.0, 0.0],  # behind its long side: blocked unless it is turned 90°
        ]
    )
    hits = segment_hits_boxes(start, ends, np.stack([centre] * 2), np.stack([half] * 2), [0, 90])
    assert hits[:, 0].tolist() == [True, False, False, True, False, True]
    assert hits[:, 1].tolist() == [True, False, False, True, False, False]  # turned 90°


@pytest.fixture(scope="module")
def scenes() -> list[Scene]:
    return [build_scene(get_episode(task, 0)) for task in all_tasks()]


def test_overhead_image_up_is_world_y_and_right_is_world_x(scenes: list[Scene]) -> None:
    for scene in scenes:
        centre = np.array(scene.episode.uav_start.pos)
        pts = centre + np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0]])
        uv, _ = project_points(scene.model, scene.data, CAM_OVERHEAD, pts, SIZE, SIZE)
        du_x, dv_x = uv[1] - uv[0]
        du_y, dv_y = uv[2] - uv[0]
        assert du_x > 10 * abs(dv_x), "world +x must point image right"
        assert -dv_y > 10 * abs(du_y), "world +y must point image up"


def test_both_views_hold_the_uav_start_and_every_framed_object(scenes: list[Scene]) -> None:
    for scene in scenes:
        ep = scene.episode
        points, margins = framing_points(ep)
        half_room = environment(ep.environment).room_half_size - WALL_CLEARANCE
        for view in THIRD_PERSON_CAMERAS:
            cam = scene.model.camera(view)
            forward = -scene.data.cam_xmat[cam.id].reshape(3, 3)[:, 2]
            pos = scene.data.cam_xpos[cam.id]
            assert np.abs(pos[:2]).max() <= half_room + 1e-9, (ep.task_id, view)
            assert fits(pos, forward, float(cam.fovy[0]), points, margins), (ep.task_id, view)
            _, inside = project_points(scene.model, scene.data, view, points, SIZE, SIZE)
            assert inside.all(), (ep.task_id, view)
