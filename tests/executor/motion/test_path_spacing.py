"""spaced_postures: the postures a check of a servoed path (a glide) visits lie as close as a
joint-space move's checks (docs/decisions.md, "Glides are checked as densely as joint-space
moves")."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from vlm_bench.executor.motion.arm_core import PATH_STEP, PATH_TRAVEL, spaced_postures


def _kept(postures: list[np.ndarray], points: list[np.ndarray]) -> list[int]:
    """Indices of the postures :func:`spaced_postures` keeps (it returns the same arrays)."""
    index = {id(q): i for i, q in enumerate(postures)}
    return [index[id(q)] for q in spaced_postures(postures, points)]


@settings(max_examples=200, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(1, 200),
    reach=st.floats(0.0005, 0.02),
)
def test_consecutive_checks_are_a_centimetre_apart_or_one_step(
    seed: int, n: int, reach: float
) -> None:
    """Random paths: TCP steps up to ``reach`` m, joint steps up to 0.05 rad."""
    rng = np.random.default_rng(seed)
    points = list(np.cumsum(rng.uniform(-reach, reach, (n, 3)), axis=0))
    postures = list(np.cumsum(rng.uniform(-0.05, 0.05, (n, 7)), axis=0))
    kept = _kept(postures, points)
    assert kept[0] == 0 and kept[-1] == n - 1
    for a, b in pairwise(kept):
        assert b > a
        if b == a + 1:
            continue  # one control step: nothing lies between to check
        assert np.linalg.norm(points[b] - points[a]) <= PATH_TRAVEL
        assert np.max(np.abs(postures[b] - postures[a])) <= PATH_STEP


def test_a_long_glide_is_checked_every_centimetre() -> None:
    """A 0.9 m glide in 155 control steps (tower_stacking seed 8's arc over the basket): every
    15th posture left 6 cm between checks, more than a 5 cm cube and a thin rim take; spaced by
    the TCP's travel, no two checks lie more than 1 cm apart."""
    progress = np.linspace(0.0, 1.0, 155)
    points = [np.array([0.9 * s, 0.0, 0.9]) for s in progress]
    postures = [np.full(7, 0.5 * s) for s in progress]
    kept = _kept(postures, points)
    assert np.max(np.diff([points[i][0] for i in kept])) <= PATH_TRAVEL
    assert len(kept) >= 90  # of 155; every 15th posture made 11 checks
