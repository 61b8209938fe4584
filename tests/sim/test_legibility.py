"""Legibility of the third-person views at 448², measured on segmentation renders at each
episode's start (:mod:`vlm_bench.sim.footprint`): the UAV's heading arrow is long enough in the
``overhead`` and ``side`` views, every task object shows in them, and (the issue's target, not met
yet) every task object is at least 16 px across.

CI measures a subset (seed 0 of twelve tasks spread over the suites, plus two episodes that
once failed); all 600 episodes are ``slow`` (``pytest -m slow``). The same measures, with a
summary, come from ``benchmarks/view_legibility.py``.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import make_episode
from vlm_bench.sim.constants import DEFAULT_IMAGE_SIZE
from vlm_bench.sim.footprint import (
    MIN_ARROW_PX,
    MIN_OBJECT_PX,
    Legibility,
    legibility_failures,
    measure_scene_legibility,
)
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import build_scene

TASKS = [t.id for t in all_tasks()]
SUBSET = [
    *((task, 0) for task in TASKS[::5]),
    ("cross_color_sorting", 5),  # the issue's example: mugs 5-8 px with the old framing
    ("multi_object_sorting", 0),  # a cube hidden behind a basket in the old side view
]
ALL = [(task, seed) for seed in range(10) for task in TASKS]
SETS = [
    pytest.param("subset", id="subset"),
    pytest.param("all", id="all600", marks=pytest.mark.slow),
]

# Not met at 448² by any framing that shows the work area: a bolt is 22 mm thick and needs a
# view at most 0.62 m across to reach 16 px, a nut 1.0 m, a cube 1.4 m, a cup 2.0 m; the framed
# areas (the UAV start and the task objects) are 1.2-4.6 m across (median 2.2 m), and even the
# task objects alone spread up to 2.7 m. Strict, so the test says when the views get there.
NOT_YET_16PX = pytest.mark.xfail(
    strict=True, reason="small task objects (bolts, nuts, cubes, cups) are 3-15 px at 448²"
)


_MEASURED: dict[str, list[Legibility]] = {}  # episode set -> measures, shared by the tests


@pytest.fixture(scope="module")
def renderer() -> Iterator[SnapshotRenderer]:
    rend = SnapshotRenderer(shadows=False)
    yield rend
    rend.close()


def _measured(which: str, renderer: SnapshotRenderer) -> list[Legibility]:
    if which not in _MEASURED:
        _MEASURED[which] = [
            measure_scene_legibility(
                build_scene(make_episode(task, seed)), renderer, DEFAULT_IMAGE_SIZE
            )
            for task, seed in (SUBSET if which == "subset" else ALL)
        ]
    return _MEASURED[which]


def _report(rows: list[Legibility], min_object: int) -> list[str]:
    return [
        f"{row.task} seed {row.seed}: {problem}"
        for row in rows
        for problem in legibility_failures(row, min_object=min_object)
    ]


@pytest.mark.parametrize("which", SETS)
def test_heading_arrow_is_long_enough_in_both_views(which: str, renderer: SnapshotRenderer) -> None:
    short = [
        f"{row.task} seed {row.seed}: {view} {px:.1f}px"
        for row in _measured(which, renderer)
        for view, px in row.arrow.items()
        if px < MIN_ARROW_PX
    ]
    assert not short, short


@pytest.mark.parametrize("which", SETS)
def test_every_task_object_shows_in_both_views(which: str, renderer: SnapshotRenderer) -> None:
    """The legibility criterion with a 1 px floor: no task object is out of a view or hidden
    behind another object; the robot may cover one in a view if the other shows it."""
    problems = _report(_measured(which, renderer), min_object=1)
    assert not problems, problems


@NOT_YET_16PX
@pytest.mark.parametrize("which", SETS)
def test_every_task_object_is_16px_across(which: str, renderer: SnapshotRenderer) -> None:
    """The issue's criterion (see :mod:`vlm_bench.sim.footprint`): at least
    :data:`MIN_OBJECT_PX` across in both views, or in one where the robot covers it in the
    other."""
    problems = _report(_measured(which, renderer), min_object=MIN_OBJECT_PX)
    assert not problems, problems[:20]


def test_measures_see_the_issue_example(renderer: SnapshotRenderer) -> None:
    """The measure itself: the cups and mugs of cross_color_sorting seed 5 are task objects seen
    in both views, and hiding the robot never makes an object smaller."""
    row = next(r for r in _measured("subset", renderer) if r.task == "cross_color_sorting")
    assert {"yellow_mug", "black_mug", "green_cup"} <= set(row.objects)
    for prints in row.objects.values():
        for fp in prints.values():
            assert 0 < fp.seen <= fp.clear
            assert fp.seen <= fp.long
