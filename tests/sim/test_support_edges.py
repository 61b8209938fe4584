"""The vertical edges a support's height is read along (vlm_bench.sim.support_edges)."""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes import get_episode
from vlm_bench.sim.support_edges import (
    COLUMN_SIDE,
    MAX_EDGE_PITCH,
    floor_support,
    height_edges,
    height_supports,
)
from vlm_bench.types.episode import EpisodeObject


def _table(yaw: float = 0.0) -> EpisodeObject:
    return EpisodeObject(
        id="t",
        kind="table",
        color="white",
        pos=(1.0, 2.0, 0.0),
        yaw_deg=yaw,
        on="floor",
        role="support",
    )


@pytest.mark.parametrize("yaw", [0.0, 30.0, 90.0])
def test_the_four_edges_run_from_the_top_corners_down_to_the_floor(yaw: float) -> None:
    edges = height_edges(_table(yaw))
    sx, sy, sz = object_kind("table").size
    assert len(edges) == 4
    for edge in edges:
        assert edge.top[2] == pytest.approx(sz) and edge.floor[2] == 0.0
        assert np.allclose(edge.top[:2], edge.floor[:2])
        # A corner lies half the box's diagonal from the centre; its column is inside the box.
        assert np.hypot(*(edge.top[:2] - (1.0, 2.0))) == pytest.approx(np.hypot(sx, sy) / 2)
        assert np.all(np.linalg.norm(edge.column[:, :2] - edge.top[:2], axis=1) <= 2 * COLUMN_SIDE)
        assert np.allclose(np.linalg.norm(edge.normals, axis=1), 1.0)
        assert edge.axis[0][2] == 0.0 and edge.axis[1][2] == pytest.approx(sz)


def test_an_edge_shows_its_height_only_to_a_camera_it_faces_from_the_side() -> None:
    edges = height_edges(_table())
    east = np.array([6.0, 2.0, 2.0])  # far along +x, a little above the table
    facing = [e for e in edges if e.faces(east)]
    assert len(facing) == 2 and all(e.top[0] > 1.0 for e in facing)
    assert all(e.seen_from(east) for e in facing)
    assert not any(e.seen_from(east) for e in edges if e not in facing)
    above = np.array([1.8, 2.0, 5.0])  # just past the +x side, high above: a stub
    assert all(e.faces(above) and e.pitch(above) > MAX_EDGE_PITCH for e in facing)
    assert not any(e.seen_from(above) for e in edges)


def test_a_support_on_a_table_is_read_through_the_table() -> None:
    episode = get_episode("pick_left_cup_red", 0)
    supports = height_supports(episode)
    assert {"table", "red_plate"} <= set(supports)
    plate = next(o for o in episode.objects if o.id == "red_plate")
    assert floor_support(episode, "red_plate").id == plate.on
    assert floor_support(episode, "table").id == "table"
