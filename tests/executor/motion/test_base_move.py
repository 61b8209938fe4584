"""BaseMove and CollisionQuery: hand-computed cases of the base-move arithmetic and the cache
identities the IK and collision caches rely on."""

from __future__ import annotations

import math

import numpy as np

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery


def test_apply_offsets_the_position_and_turns_the_heading_about_z() -> None:
    qpos = np.array([0.0, 1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0, 9.0])  # free joint at 1, identity
    BaseMove(np.array([0.5, -0.5, 0.25]), math.pi / 2).apply(qpos, 1)
    np.testing.assert_allclose(qpos[1:4], [1.5, 1.5, 3.25])
    half = math.sqrt(0.5)
    np.testing.assert_allclose(qpos[4:8], [half, 0.0, 0.0, half], atol=1e-12)
    assert qpos[0] == 0.0 and qpos[8] == 9.0  # nothing else moves


def test_a_move_without_a_turn_leaves_the_orientation_bit_for_bit() -> None:
    quat = np.array([0.9, 0.1, -0.2, 0.3])
    qpos = np.array([0.0, 0.0, 1.0, *quat])
    BaseMove.vertical(-0.06).apply(qpos, 0)
    assert np.array_equal(qpos[3:], quat)
    assert qpos[2] == 1.0 - 0.06


def test_undo_and_plus() -> None:
    move = BaseMove(np.array([0.1, 0.2, -0.3]), 0.5)
    back = move.undo()
    np.testing.assert_array_equal(back.xyz, [-0.1, -0.2, 0.3])
    assert back.yaw == -0.5
    np.testing.assert_array_equal(move.plus(np.array([1.0, 0.0, 0.0])).xyz, [1.1, 0.2, -0.3])
    assert move.plus(np.zeros(3)).yaw == 0.5


def test_the_turn_is_made_at_the_higher_end() -> None:
    assert BaseMove(np.array([0.0, 0.0, -0.1]), 1.0).turns_first  # before a descent
    assert not BaseMove(np.array([0.0, 0.0, 0.1]), 1.0).turns_first  # after a climb
    assert not BaseMove(np.array([0.3, 0.0, 0.0]), 1.0).turns_first  # after a level move


def test_cache_keys_follow_the_values() -> None:
    a = BaseMove(np.array([0.1, 0.0, 0.0]))
    assert a.key() == BaseMove(np.array([0.1, 0.0, 0.0]), 0.0).key()
    assert a.key() != BaseMove(np.array([0.1, 0.0, 0.0]), 0.1).key()
    q1 = CollisionQuery.of({3, 1}, 0.04, a)
    q2 = CollisionQuery.of(frozenset({1, 3}), 0.04, BaseMove(np.array([0.1, 0.0, 0.0])))
    assert q1.key() == q2.key()
    assert q1.near(0.01).key() != q1.key()
    assert q1.near(0.01).ignore == q1.ignore
