"""Snapshot rendering, contact sheets, and set-of-marks projection and labels."""

from __future__ import annotations

import os

import mujoco
import numpy as np
import pytest
from numpy.typing import NDArray

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.sim.framing import view_xyaxes
from vlm_bench.sim.labels import draw_labels, project_points
from vlm_bench.sim.render import SnapshotRenderer, contact_sheet

# Small bright markers at known world points, seen by two cameras.
MARKERS = np.array([[0.0, 0.0, 0.5], [0.45, -0.3, 0.2], [-0.5, 0.4, 0.9], [0.2, 0.55, 0.05]])
CAMERAS = {
    "front": ((2.0, -1.2, 1.4), (0.0, 0.0, 0.4)),
    "high": ((-0.6, -0.4, 2.6), (0.0, 0.1, 0.3)),
}


def scene(markers: NDArray[np.float64] | None = None) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Grey floor, a box with a shadow, cameras, and optionally one emissive red ball per marker."""
    spec = mujoco.MjSpec()
    spec.visual.global_.offwidth = spec.visual.global_.offheight = 1024
    world = spec.worldbody
    world.add_light(
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, dir=[0.3, 0.2, -1.0], pos=[-1.5, -1, 5],
        diffuse=[0.6] * 3, ambient=[0.3] * 3, castshadow=True,
    )  # fmt: skip
    world.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.5], rgba=[0.5, 0.5, 0.5, 1])
    world.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.1, 0.1, 0.1], pos=[-0.2, -0.4, 0.1],
        rgba=[0.2, 0.3, 0.8, 1],
    )  # fmt: skip
    if markers is not None:
        glow = spec.add_material(name="glow")
        glow.emission = 1.0
        glow.rgba = [1.0, 0.0, 0.0, 1.0]
        for k, p in enumerate(markers):
            world.add_geom(
                name=f"marker{k}", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.015, 0, 0],
                pos=list(p), material="glow",
            )  # fmt: skip
    for name, (pos, target) in CAMERAS.items():
        world.add_camera(
            name=name, pos=list(pos), xyaxes=view_xyaxes(np.subtract(target, pos)), fovy=50
        )
    ortho = ((0.3, -2.5, 1.5), (0.0, 0.0, 0.4))
    world.add_camera(
        name="ortho", pos=list(ortho[0]), xyaxes=view_xyaxes(np.subtract(ortho[1], ortho[0])),
        fovy=2.0,
        proj=mujoco.mjtProjection.mjPROJ_ORTHOGRAPHIC,
    )  # fmt: skip
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def test_headless_backend_is_the_default() -> None:
    assert os.environ.get("MUJOCO_GL")


def test_shapes_for_both_sizes_and_context_reuse(renderer: SnapshotRenderer) -> None:
    model, data = scene()
    builds = renderer.context_builds
    for size in (224, 448, 224):
        img = renderer.render(model, data, "front", size)
        assert img.shape == (size, size, 3) and img.dtype == np.uint8 and img.std() > 5
    views = renderer.render_views(model, data, ["high", "front"], 448)
    assert list(views) == ["high", "front"]
    assert all(v.shape == (448, 448, 3) for v in views.values())
    assert renderer.context_builds == builds + 1  # one upload for the model, reused by all sizes
    np.testing.assert_array_equal(renderer.render(model, data, "front", 448), views["front"])
    other, other_data = scene()
    renderer.render(other, other_data, "front", 224)
    assert renderer.context_builds == builds + 2  # a new model is uploaded once


def test_render_errors_name_the_problem(renderer: SnapshotRenderer) -> None:
    model, data = scene()
    with pytest.raises(UnknownNameError, match="front"):
        renderer.render(model, data, "nope", 224)
    with pytest.raises(ConfigError, match="offscreen"):
        renderer.render(model, data, "front", 2048)


def test_shadow_flag_and_close_then_reuse() -> None:
    model, data = scene()
    r = SnapshotRenderer(shadows=True)
    with_shadow = r.render(model, data, "front", 224).astype(int)
    r.shadows = False
    without = r.render(model, data, "front", 224).astype(int)
    r.close()
    again = r.render(model, data, "front", 224).astype(int)  # re-creates its context
    r.close()
    assert with_shadow.sum() < without.sum()  # the shadow only darkens
    assert np.abs(with_shadow - without).max() > 30
    np.testing.assert_array_equal(again, without)


@pytest.mark.parametrize("camera", [*sorted(CAMERAS), "ortho"])
def test_projection_lands_on_the_rendered_marker(renderer: SnapshotRenderer, camera: str) -> None:
    model, data = scene(MARKERS)
    size = 448
    img = renderer.render(model, data, camera, size).astype(int)
    uv, visible = project_points(model, data, camera, MARKERS, size, size)
    assert visible.all()
    red = (img[..., 0] > 200) & (img[..., 1] < 60) & (img[..., 2] < 60)
    rows, cols = np.nonzero(red)
    for u, v in uv:
        near = (np.abs(cols + 0.5 - u) < 12) & (np.abs(rows + 0.5 - v) < 12)
        assert near.sum() >= 4, (camera, u, v)
        centroid = np.array([cols[near].mean() + 0.5, rows[near].mean() + 0.5])
        assert np.abs(centroid - [u, v]).max() <= 2.0, (camera, centroid, (u, v))


def test_projection_flags_points_behind_or_outside(renderer: SnapshotRenderer) -> None:
    model, data = scene()
    pos = np.array(CAMERAS["front"][0])
    points = np.array([pos + (pos - [0, 0, 0.4]), [0.0, 0.0, 0.4], [0.0, 30.0, 0.4]])
    uv, visible = project_points(model, data, "front", points, 224, 224)
    assert visible.tolist() == [False, True, False]
    np.testing.assert_allclose(uv[1], [112.0, 112.0], atol=1e-6)  # the look-at target: centre
    with pytest.raises(UnknownNameError):
        project_points(model, data, "nope", points, 224, 224)


def test_labels_change_pixels_only_near_the_label() -> None:
    image = np.full((224, 224, 3), 90, dtype=np.uint8)
    point = (80.0, 120.0)
    out = draw_labels(image, [("red_cup_1", point)])
    assert out.shape == image.shape and out.dtype == np.uint8
    assert (image == 90).all()  # input untouched
    rows, cols = np.nonzero((out != image).any(axis=2))
    assert len(rows) > 100
    assert np.hypot(cols + 0.5 - point[0], rows + 0.5 - point[1]).max() < 90
    assert (out == 255).all(axis=2).sum() > 50  # a white tag
    assert (out.max(axis=2) < 60).sum() > 20  # dark text / outline


def test_labels_stay_inside_the_image_and_skip_outside_points() -> None:
    image = np.zeros((224, 224, 3), dtype=np.uint8)
    corners = [("a_long_label_1", (222.0, 2.0)), ("b_long_label_2", (1.0, 222.0))]
    out = draw_labels(image, corners)
    white = (out == 255).all(axis=2)
    assert white[:60, 112:].sum() > 100  # tag of the top-right point, pulled inside
    assert white[164:, :112].sum() > 100  # tag of the bottom-left point
    untouched = draw_labels(image, [("far", (500.0, -3.0))])
    np.testing.assert_array_equal(untouched, image)


def test_overlapping_labels_do_not_cover_each_other() -> None:
    image = np.zeros((224, 224, 3), dtype=np.uint8)
    one = draw_labels(image, [("red_cup_1", (110.0, 110.0))])
    two = draw_labels(image, [("red_cup_1", (110.0, 110.0)), ("red_cup_2", (112.0, 112.0))])
    assert (two == 255).all(axis=2).sum() > 1.6 * (one == 255).all(axis=2).sum()


def test_contact_sheet_tiles_and_captions() -> None:
    colours = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0), (0, 255, 255)]
    tiles = {f"view_{k}": np.full((64, 80, 3), c, dtype=np.uint8) for k, c in enumerate(colours)}
    sheet = np.asarray(contact_sheet(tiles, title=None, columns=2))
    titled = np.asarray(contact_sheet(tiles, title="Task 12", columns=2))
    assert titled.shape[0] > sheet.shape[0] and titled.shape[1] == sheet.shape[1]
    assert sheet.shape[1] > 2 * 80 and sheet.shape[1] < 3 * 80
    for c in colours:  # each tile pasted whole
        assert (sheet == c).all(axis=2).sum() == 64 * 80
    assert (sheet.max(axis=2) < 80).sum() > 50  # dark caption text
    wide = np.asarray(contact_sheet(dict(list(tiles.items())[:2]), columns=4))
    assert wide.shape[1] < 3 * 80  # never wider than the tiles need
    with pytest.raises(ConfigError):
        contact_sheet({})
