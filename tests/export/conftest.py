"""Shared fixtures: small dataset exports, written once per test session."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from vlm_bench.export.dataset_export import DatasetExport, export_dataset
from vlm_bench.export.options import ExportOptions, export_options

SMALL = {"tasks": ("standard_pick_place", "drawer_interaction"), "seeds": (0,), "resolution": 64}
"""Two tasks × seed 0 × both instructions at 64 px: four rows, quick to render."""


@pytest.fixture(scope="session")
def snapshot_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A PNG cache the exports and prompts of this session share (renders once)."""
    return tmp_path_factory.mktemp("snapshots")


@pytest.fixture(scope="session")
def exporter(
    tmp_path_factory: pytest.TempPathFactory, snapshot_cache: Path
) -> Callable[..., DatasetExport]:
    """``exporter(name, **options)``: a dataset folder of those options (memoised by name)."""
    made: dict[str, DatasetExport] = {}

    def export(name: str, **fields: object) -> DatasetExport:
        if name not in made:
            options: ExportOptions = export_options(**fields)
            out = tmp_path_factory.mktemp("datasets") / name
            made[name] = export_dataset(
                out, options, snapshot_cache=snapshot_cache, progress=False, shard_rows=3
            )
        return made[name]

    return export


@pytest.fixture(scope="session")
def small(exporter: Callable[..., DatasetExport]) -> DatasetExport:
    """The :data:`SMALL` export, in shards of three rows."""
    return exporter("small", **SMALL)
