"""Shared executor test set-ups; ``incidents`` (frozen incident scenes) is importable here."""

from __future__ import annotations

import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import set_arm_targets
from vlm_bench.sim.scene import build_scene

sys.path.insert(0, str(Path(__file__).parent))  # --import-mode=importlib puts no test dir there

SIDEWAYS = (1.65, -1.75, 2.55, -2.56, -0.61, 1.28, -1.33)
"""An arm reaching out sideways: the straight stow from here swings link 6 through the UAV."""


@pytest.fixture
def sideways_hand() -> Hand:
    """The hand of a ``standard_pick_place`` seed 0 scene with the arm put at :data:`SIDEWAYS`
    (servo targets there too, fingers open)."""
    loop = SimLoop(build_scene(get_episode("standard_pick_place", 0)))
    hand = Hand(loop)
    out = np.asarray(SIDEWAYS)
    loop.data.qpos[hand.core.ik.qadr] = out
    set_arm_targets(loop.model, loop.data, out, c.GRIPPER_OPEN)
    mujoco.mj_forward(loop.model, loop.data)
    return hand
