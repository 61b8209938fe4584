"""Layout rules: objects a top-down hand must close across keep room from taller neighbours."""

from __future__ import annotations

import pytest

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes.layout import check_layout
from vlm_bench.types.episode import EpisodeObject


def _obj(oid: str, kind: str, x: float, y: float = 0.0) -> EpisodeObject:
    return EpisodeObject(
        id=oid, kind=kind, color="gray", pos=(x, y, 0.75), yaw_deg=0.0, on="table", role="target"
    )


def _table() -> EpisodeObject:
    return EpisodeObject(
        id="table",
        kind="table",
        color="wood",
        pos=(0.0, 0.0, 0.0),
        yaw_deg=0.0,
        on="floor",
        role="support",
    )


# A basket is 0.32 m long (x), 0.15 m tall; a banana lies along x, 0.06 m wide (y).
@pytest.mark.parametrize(
    ("kind", "gap", "ok"),
    [
        ("banana", 0.05, False),  # closing across y, the 0.2 m hand would land on the rim
        ("banana", 0.09, True),
        ("cube", 0.05, True),  # fits the open hand whichever way: it turns to the free side
        ("cube", 0.02, False),  # ...but even the hand's 6 cm thickness needs some room
        ("bowl", 0.03, True),  # held by the rim, from any free side
    ],
)
def test_long_objects_keep_a_hands_room_from_taller_neighbours(
    kind: str, gap: float, ok: bool
) -> None:
    half = object_kind(kind).size[1] / 2
    objects = [_table(), _obj("basket", "basket", 0.0), _obj("thing", kind, 0.0, 0.12 + gap + half)]
    if ok:
        check_layout(objects)
    else:
        with pytest.raises(ValueError, match="overlaps"):
            check_layout(objects)


def test_beyond_a_long_objects_end_the_hands_thickness_is_enough() -> None:
    # The banana lies along x; the hand closes across y, so a basket off its end (x) meets
    # only the hand's 6 cm thickness: 5 cm is room enough there, unlike across its width.
    half_len = object_kind("banana").size[0] / 2
    basket_half = object_kind("basket").size[0] / 2
    x = basket_half + 0.05 + half_len
    check_layout([_table(), _obj("basket", "basket", 0.0), _obj("banana", "banana", x)])
