"""Labels keep off the task objects; the view checks read segmentation renders."""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.sim.labels import _overlap, tag_layout
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import build_scene
from vlm_bench.sim.support_edges import height_supports
from vlm_bench.sim.view_checks import (
    label_overlaps,
    support_heights,
    support_tops,
    view_segmentations,
)


def test_a_tag_moves_off_an_object_box_where_it_would_go_first() -> None:
    point = (200.0, 200.0)
    ((_, _, first),) = tag_layout((448, 448), [("gray_cube_2", point)])
    ((_, _, moved),) = tag_layout((448, 448), [("gray_cube_2", point)], avoid=[first])
    assert _overlap(first, moved) == 0.0
    # Boxes all round the point: the tag goes further out rather than over one.
    ring = [(150.0, 150.0, 250.0, 250.0)]
    ((_, _, far),) = tag_layout((448, 448), [("gray_cube_2", point)], avoid=ring)
    assert _overlap(far, ring[0]) == 0.0


@pytest.fixture(scope="module")
def renderer() -> SnapshotRenderer:
    return SnapshotRenderer(shadows=False)


@pytest.mark.parametrize("seed", [0, 4])
def test_no_label_covers_a_task_object(renderer: SnapshotRenderer, seed: int) -> None:
    scene = build_scene(get_episode("color_distractor_green", seed))
    assert any(o.label for o in scene.episode.objects)  # the case has labels to place
    assert label_overlaps(scene, renderer) == []


def test_supports_under_task_objects_are_checked_in_both_views(renderer: SnapshotRenderer) -> None:
    episode = get_episode("pick_left_cup_red", 0)
    supports = height_supports(episode)
    assert "table" in supports
    seen = support_heights(build_scene(episode), renderer)
    assert set(seen) == set(supports)
    assert all(set(views) == {"overhead", "side"} for views in seen.values())


def test_a_support_top_is_seen_unless_the_view_is_cut_or_covered(
    renderer: SnapshotRenderer,
) -> None:
    episode = get_episode("pick_left_cup_red", 0)
    scene = build_scene(episode)
    segs = view_segmentations(scene, renderer)
    tops = support_tops(scene, renderer, segs=segs)
    assert set(tops) == set(height_supports(episode)) and any(tops["table"].values())
    # The same views with every pixel turned to background: no top is seen.
    empty = {view: np.full_like(seg, -1) for view, seg in segs.items()}
    assert not any(any(v.values()) for v in support_tops(scene, renderer, segs=empty).values())


def test_a_table_shows_its_full_height_only_while_its_legs_reach_the_floor_in_view(
    renderer: SnapshotRenderer,
) -> None:
    """color_distractor_green seed 1: the side view shows the table's near legs down to the
    floor. Erase its legs' pixels, or their lower half, and the view shows its top but not
    its height."""
    scene = build_scene(get_episode("color_distractor_green", 1))
    segs = view_segmentations(scene, renderer)
    assert support_heights(scene, renderer, segs=segs)["table"]["side"]
    legs = [scene.model.geom(f"table/leg{k}").id for k in range(4)]
    on_legs = np.isin(segs["side"], legs)
    rows = np.nonzero(on_legs.any(axis=1))[0]
    lower = on_legs & (np.arange(on_legs.shape[0]) > (rows.min() + rows.max()) / 2)[:, None]
    for erased in (on_legs, lower):
        cut = dict(segs, side=np.where(erased, -1, segs["side"]))
        assert support_tops(scene, renderer, segs=cut)["table"]["side"]
        assert not support_heights(scene, renderer, segs=cut)["table"]["side"]
