"""Supports at varied heights: at seeds 1-9 each table of a task is built as one of three height
variants from the catalogue, drawn per table; seed 0 keeps the task file's 0.75 m table; what
stands on a table rests on its top; working altitudes over two tables differ by either nothing
or clearly more than the vertical threshold."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from vlm_bench.catalog.tasks import get_task
from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes.generate import make_episode
from vlm_bench.episodes.layout import TABLE_KINDS, place_objects, support_kinds
from vlm_bench.rules.approach import VERTICAL_MARGIN
from vlm_bench.sim.objects.builder_kit import OBJECT_BUILDERS
from vlm_bench.types.geometry import APPROACH

TWO_TABLES = "place_on_flat_surface"  # a cube on one table goes onto a plate on another


def test_table_tops_are_apart_by_the_threshold_and_its_margin() -> None:
    tops = sorted(object_kind(k).size[2] for k in TABLE_KINDS)
    assert tops == [0.40, 0.75, 1.10]
    for a, b in itertools.pairwise(tops):
        assert b - a >= APPROACH.vertical_threshold + VERTICAL_MARGIN + 0.05 - 1e-9
    assert all(k in OBJECT_BUILDERS for k in TABLE_KINDS)


def test_the_canonical_layout_keeps_the_task_files_tables() -> None:
    task = get_task(TWO_TABLES)
    assert set(support_kinds(task, None).values()) == {"table"}
    assert {o.kind for o in make_episode(TWO_TABLES, 0).objects if o.on == "floor"} == {"table"}


def test_each_table_draws_its_height_and_every_variant_occurs() -> None:
    task = get_task(TWO_TABLES)
    draws = [support_kinds(task, np.random.default_rng(i)) for i in range(40)]
    assert {k for d in draws for k in d.values()} == set(TABLE_KINDS)
    assert any(len(set(d.values())) == 2 for d in draws)  # two tables, two heights


@pytest.mark.parametrize("variant", TABLE_KINDS)
def test_objects_rest_on_the_top_of_the_table_they_stand_on(variant: str) -> None:
    task = get_task(TWO_TABLES)
    objects = place_objects(task, None, {t: variant for t in support_kinds(task, None)})
    by_id = {o.id: o for o in objects}
    top = object_kind(variant).size[2]
    for obj in objects:
        if obj.on != "floor" and by_id[obj.on].kind == variant:
            assert obj.pos[2] == pytest.approx(top), obj.id


def test_later_segments_climb_or_descend_between_tables_of_two_heights() -> None:
    """Seeds 1-9 of a two-table task: the second segment's vertical move is not the same in
    every seed (the issue's aim: later moves that vary, not one pattern per task)."""
    patterns = set()
    for seed in range(1, 10):
        plan = make_episode(TWO_TABLES, seed).gt_plan
        arm = [i for i, s in enumerate(plan) if s.tasktype == "ARM"]
        second = plan[arm[0] + 1 : arm[1]]
        patterns.add(tuple(s.direction.value for s in second if not s.direction.is_horizontal))
    assert len(patterns) >= 2, patterns
