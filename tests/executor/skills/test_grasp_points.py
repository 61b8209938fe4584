"""Grasp points per object kind: fingers close across the narrow side; mugs and bowls are held
by the rim."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.skills.grasp_points import (
    MAX_ACROSS,
    MUG_RIM_INSET,
    RIM_INSET,
    grasp_points,
)


def _closing_axes(rotations: tuple[np.ndarray, ...]) -> list[np.ndarray]:
    return [r[:, 1] for r in rotations]  # the fingers close along the hand's y axis


def _box(size: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    half = np.array([size[0] / 2, size[1] / 2, 0.0])
    return -half, half + np.array([0.0, 0.0, size[2]])


@pytest.mark.parametrize("yaw_deg", [0.0, 30.0, 90.0])
def test_long_objects_are_held_across_their_width(yaw_deg: float) -> None:
    kind = object_kind("banana")  # 0.19 x 0.06 m
    yaw = math.radians(yaw_deg)
    lo, hi = _box(kind.size)
    (cand,) = grasp_points(kind, np.zeros(3), yaw, lo, hi)
    width_axis = np.array([-math.sin(yaw), math.cos(yaw), 0.0])
    for axis in _closing_axes(cand.rotations):
        assert abs(float(axis @ width_axis)) == pytest.approx(1.0)
    assert len(cand.rotations) == 2


def test_a_bolt_is_held_across_its_shaft_level_with_its_centre_of_mass() -> None:
    kind = object_kind("bolt")  # 0.07 x 0.022 m: fits the open hand, but only end to end
    com = np.array([-0.012, 0.004, 0.011])  # towards the heavy head (-x), a little off-axis
    (cand,) = grasp_points(kind, np.zeros(3), 0.0, *_box(kind.size), com)
    assert len(cand.rotations) == 2
    for axis in _closing_axes(cand.rotations):
        assert abs(float(axis[1])) == pytest.approx(1.0)  # across the shaft
    assert cand.point[:2] == pytest.approx([-0.012, 0.0])  # moved along the length only


def test_small_objects_allow_four_headings() -> None:
    kind = object_kind("cube")
    assert max(kind.size[:2]) <= MAX_ACROSS
    (cand,) = grasp_points(kind, np.zeros(3), 0.0, *_box(kind.size))
    assert len(cand.rotations) == 4


@pytest.mark.parametrize("yaw_deg", [0.0, 19.5, -70.0])
def test_a_nut_is_held_across_two_flats(yaw_deg: float) -> None:
    """Closing on two corners, the pads push the nut round (contextual_spare_part seed 4's
    nut, against a bin's wall, was reachable only on a flat pair's heading)."""
    from vlm_bench.sim.objects.industrial import NUT_FLAT_DEG

    kind = object_kind("nut")
    yaw = math.radians(yaw_deg)
    (cand,) = grasp_points(kind, np.zeros(3), yaw, *_box(kind.size))
    assert len(cand.rotations) == 6
    normals = {round((NUT_FLAT_DEG + 60.0 * k + yaw_deg) % 360.0, 6) for k in range(6)}
    for axis in _closing_axes(cand.rotations):
        deg = round(math.degrees(math.atan2(axis[1], axis[0])) % 360.0, 6)
        assert (
            min(abs(deg - n) for n in normals) < 1e-6
            or min(abs(abs(deg - n) - 360.0) for n in normals) < 1e-6
        )


def test_mug_is_held_by_the_rim_away_from_its_handle() -> None:
    kind = object_kind("mug")  # 0.11 x 0.08: the handle fills the last 3 cm of +x
    cands = grasp_points(kind, np.array([1.0, 2.0, 0.75]), 0.0, *_box(kind.size))
    axis = np.array([1.0 - 0.015, 2.0])  # the cup's axis
    assert len(cands) == 5
    assert cands[0].point[:2] == pytest.approx([axis[0] - 0.0335, 2.0])  # opposite the handle
    for cand in cands:
        offset = cand.point[:2] - axis
        assert np.linalg.norm(offset) == pytest.approx(0.04 - MUG_RIM_INSET)  # mid-wall
        assert offset[0] <= 1e-9  # never on the handle's side
        for closing in _closing_axes(cand.rotations):
            assert abs(float(closing[:2] @ offset)) / np.linalg.norm(offset) == pytest.approx(1.0)


def test_bowl_is_held_by_its_rim_closing_radially() -> None:
    kind = object_kind("bowl")  # 0.16 m across
    lo, hi = _box(kind.size)
    cands = grasp_points(kind, np.zeros(3), 0.0, lo, hi)
    assert len(cands) == 8
    for cand in cands:
        radial = cand.point[:2] / np.linalg.norm(cand.point[:2])
        assert np.linalg.norm(cand.point[:2]) == pytest.approx(0.08 - RIM_INSET)
        for axis in _closing_axes(cand.rotations):
            assert abs(float(axis[:2] @ radial)) == pytest.approx(1.0)


def test_a_curved_banana_is_held_on_its_middle_not_its_bounding_box() -> None:
    """Yawed 19°, the banana's world bounding box is centred 1.4 cm off its body axis and
    2.3 cm off the middle of the arc; the fingers (1 cm clear each side) must close on the
    middle section: the grasp is centred on the collision geoms between them."""
    from incidents import incident_episode

    from vlm_bench.executor.sim_loop import SimLoop
    from vlm_bench.executor.skills.grasping import Picker
    from vlm_bench.executor.skills.hand import Hand
    from vlm_bench.sim.objects.bounds import object_bounds
    from vlm_bench.sim.objects.groceries import _banana_axis
    from vlm_bench.sim.scene import build_scene

    episode = incident_episode("drawer_interaction", 1)
    scene = build_scene(episode)
    picker = Picker(Hand(SimLoop(scene)))
    body = scene.data.body("banana")
    rot = np.array(body.xmat).reshape(3, 3)
    kind = object_kind("banana")
    lo, hi = object_bounds(scene.model, scene.data, "banana", solid_only=True)
    (cand,) = grasp_points(kind, np.array(body.xpos), math.atan2(rot[1, 0], rot[0, 0]), lo, hi)
    point = picker.on_section("banana", cand.point, cand.rotations[0])
    rings = _banana_axis(*kind.size)
    middle_y = rings[len(rings) // 2][0][1]  # the arc's middle, across the banana (body frame)
    assert abs(float((rot.T @ (cand.point - body.xpos))[1]) - middle_y) > 0.015  # the box's
    assert float((rot.T @ (point - body.xpos))[1]) == pytest.approx(middle_y, abs=0.003)


@pytest.mark.parametrize("yaw_deg", [0.0, 30.0, 90.0])
def test_a_cleanser_is_held_by_its_cap_with_no_pad_on_the_nozzle(yaw_deg: float) -> None:
    """function_detergent seed 7: one pad on the nozzle's 8 mm end (the bottle's +x) held the
    bottle in a grip unstable about the vertical, and the place swung it out of the fingers.
    Every candidate's fingers close square to the nozzle, on the cap's round sides."""
    kind = object_kind("cleanser")
    yaw = math.radians(yaw_deg)
    nozzle = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    lo, hi = _box(kind.size)
    cands = grasp_points(kind, np.zeros(3), yaw, lo, hi)
    assert cands
    for cand in cands:
        assert np.allclose(cand.point[:2], 0.0)
        assert hi[2] - 0.028 < cand.point[2] < hi[2]  # on the cap
        for axis in _closing_axes(cand.rotations):
            assert abs(float(np.dot(axis, nozzle))) < 1e-9
