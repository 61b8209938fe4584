"""The legible views (vlm_bench.sim.legible_views): the standard framing where it is legible,
else a close-up that still frames the whole work area."""

from __future__ import annotations

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import get_task
from vlm_bench.episodes.layout import place_objects
from vlm_bench.sim.cameras import SIDE_MIN_ARROW, heading_arrow_ends, third_person_views
from vlm_bench.sim.constants import CAM_SIDE
from vlm_bench.sim.framing import image_span
from vlm_bench.sim.height_views import shown_views
from vlm_bench.sim.legible_views import legible_views
from vlm_bench.sim.view_sizes import frame_problem, legibility_score, object_pixel_sizes
from vlm_bench.types.episode import Episode


def _episode(task: str, seed: int) -> Episode:
    return load_materialised(get_task(task)).episodes[seed]


def _score(ep: Episode, views: dict) -> float:  # type: ignore[type-arg]
    return legibility_score(ep, object_pixel_sizes(ep, views=views))


def test_a_legible_episode_keeps_the_standard_framing() -> None:
    ep = _episode("standard_pick_place", 9)  # version 3: legible in the standard framing
    standard, shown = third_person_views(ep), legible_views(ep)
    assert _score(ep, standard) >= 1.0
    for name, view in standard.items():
        assert (shown[name].pos == view.pos).all() and shown[name].fovy == view.fovy


def test_a_close_up_enlarges_the_least_legible_object_and_frames_the_work_area() -> None:
    """variant_banana_in_bowl seed 0 (canonical layout, UAV 1.3 m or more away) shows its
    least legible object at about half the bound in the standard framing."""
    ep = _episode("variant_banana_in_bowl", 0)
    standard, shown = third_person_views(ep), legible_views(ep)
    assert _score(ep, standard) < 0.6
    assert _score(ep, shown) > 1.5 * _score(ep, standard)
    assert frame_problem(ep, shown) is None
    side = shown[CAM_SIDE]
    assert image_span(side.pos, side.forward, side.fovy, *heading_arrow_ends(ep)) >= SIDE_MIN_ARROW


def test_a_seed_0_short_in_the_close_up_too_gets_another_start_and_keeps_its_objects() -> None:
    """target_color_yellow seed 0's canonical start left a 5 cm cube at half the bound even in
    the close-up; a later start is legible in the views it is shown with."""
    task = get_task("target_color_yellow")
    ep = _episode(task.id, 0)
    assert legibility_score(ep, ep.object_px) >= 1.0
    assert ep.object_px == object_pixel_sizes(ep, views=shown_views(ep))
    assert list(ep.objects) == place_objects(task, None)
