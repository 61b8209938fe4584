"""The views an episode is shown with (vlm_bench.sim.height_views): the legible views, with the
side camera moved where they leave a table's full height unseen, never less legible."""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import get_task
from vlm_bench.sim import height_views
from vlm_bench.sim.cameras import (
    SIDE_MIN_ARROW,
    CameraView,
    heading_arrow_ends,
    side_forward,
)
from vlm_bench.sim.constants import CAM_OVERHEAD, CAM_SIDE
from vlm_bench.sim.framing import closest_fit, image_span
from vlm_bench.sim.height_sight import heights_shown
from vlm_bench.sim.height_views import KEPT_LEGIBILITY, camera_poses, shown_views
from vlm_bench.sim.legible_views import hiding, legible_views, side_legibility
from vlm_bench.sim.scene import build_spec
from vlm_bench.sim.support_edges import height_edges
from vlm_bench.sim.view_sizes import frame_problem, object_pixel_sizes
from vlm_bench.types.episode import Episode


def _episode(task: str, seed: int) -> Episode:
    return load_materialised(get_task(task)).episodes[seed]


def _legibility(ep: Episode, views: dict[str, CameraView]) -> dict[str, float]:
    side = views[CAM_SIDE]
    return side_legibility(ep, views[CAM_OVERHEAD])(side, hiding(ep)(side.pos))


def test_the_side_camera_moves_to_show_the_tables_down_to_the_floor() -> None:
    """pick_left_cup_red seed 1: the legible views cut the tables' legs off; the shown side
    camera frames them, each object as legible up to the kept ratio, with the work area and
    the heading arrow in view."""
    ep = _episode("pick_left_cup_red", 1)
    legible, shown = legible_views(ep), shown_views(ep)
    assert not all(heights_shown(ep, legible).values())
    assert all(heights_shown(ep, shown).values())
    assert (shown[CAM_OVERHEAD].pos == legible[CAM_OVERHEAD].pos).all()
    before, after = _legibility(ep, legible), _legibility(ep, shown)
    assert all(after[k] >= min(ratio, KEPT_LEGIBILITY) for k, ratio in before.items())
    assert frame_problem(ep, shown) is None
    side = shown[CAM_SIDE]
    assert image_span(side.pos, side.forward, side.fovy, *heading_arrow_ends(ep)) >= SIDE_MIN_ARROW


def test_views_that_show_every_height_stay() -> None:
    ep = _episode("container_geometry_bowl", 3)
    legible = legible_views(ep)
    assert all(heights_shown(ep, legible).values())
    assert all((shown.pos == legible[name].pos).all() for name, shown in shown_views(ep).items())


def test_the_scene_and_the_recorded_sizes_use_the_shown_views() -> None:
    ep = _episode("pick_left_cup_red", 1)
    shown = shown_views(ep)
    side = next(cam for cam in build_spec(ep).cameras if cam.name == CAM_SIDE)
    assert side.fovy == shown[CAM_SIDE].fovy and list(side.pos) == shown[CAM_SIDE].pos.tolist()
    assert ep.object_px == object_pixel_sizes(ep, views=shown)


def test_an_episode_records_its_cameras_and_building_its_scene_searches_nothing(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The committed episode carries the cameras the search chooses (to the last few bits: the
    search's floats differ in their last digit between CPUs); a scene built from it (every
    execution builds one) reads them, bit for bit, and runs no search; an episode without
    them (an older file) gets them searched."""
    ep = _episode("pick_left_cup_red", 1)
    searched = camera_poses(shown_views(ep.model_copy(update={"cameras": {}})))
    assert set(ep.cameras) == set(searched) == {CAM_OVERHEAD, CAM_SIDE}
    for name, pose in ep.cameras.items():
        assert pose.pos == pytest.approx(searched[name].pos, abs=1e-12)
        assert pose.forward == pytest.approx(searched[name].forward, abs=1e-12)
        assert pose.fovy == searched[name].fovy

    def no_search(_: str) -> None:
        raise AssertionError("camera search run for an episode that records its cameras")

    monkeypatch.setattr(height_views, "_shown_views", no_search)
    side = next(cam for cam in build_spec(ep).cameras if cam.name == CAM_SIDE)
    assert tuple(side.pos) == ep.cameras[CAM_SIDE].pos
    assert side.fovy == ep.cameras[CAM_SIDE].fovy
    with pytest.raises(AssertionError, match="camera search"):
        build_spec(ep.model_copy(update={"cameras": {}}))


def test_a_leg_is_predicted_shown_from_the_side_not_from_above_nor_behind_cabinets() -> None:
    """A camera south of the table framing it whole: from 20 degrees up its legs show; from
    80 degrees up they shrink to stubs; two cabinets just south of its corners hide them."""
    ep = _episode("color_distractor_green", 1)
    table = next(o for o in ep.objects if o.id == "table")
    x, y, _ = table.pos
    away = ep.uav_start.model_copy(update={"pos": (x, y + 3.0, 3.0)})  # the robot out of sight
    ep = ep.model_copy(update={"uav_start": away})
    ends = np.array([p for e in height_edges(table) for p in (e.top, e.floor)])

    def view(elevation: float) -> dict[str, CameraView]:
        forward = side_forward(-90.0, elevation)
        pos = closest_fit(forward, 50.0, ends, np.full(len(ends), 0.1))
        return {CAM_SIDE: CameraView(pos, forward, 50.0)}

    assert heights_shown(ep, view(20.0))["table"]
    assert not heights_shown(ep, view(80.0))["table"]
    cabinets = tuple(
        table.model_copy(update={"id": f"cabinet_{k}", "kind": "drawer_cabinet", "pos": pos})
        for k, pos in enumerate([(x - 0.6, y - 0.9, 0.0), (x + 0.6, y - 0.9, 0.0)])
    )
    hidden = ep.model_copy(update={"objects": ep.objects + cabinets})
    assert not heights_shown(hidden, view(20.0))["table"]
