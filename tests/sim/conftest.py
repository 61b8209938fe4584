"""Shared simulator test set-up: a renderer without shadows, one per test module."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from vlm_bench.sim.render import SnapshotRenderer


@pytest.fixture(scope="module")
def renderer() -> Iterator[SnapshotRenderer]:
    """A shadowless renderer (the fast one), closed after the module's tests."""
    with SnapshotRenderer(shadows=False) as r:
        yield r
