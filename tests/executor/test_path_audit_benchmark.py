"""``benchmarks/path_audit.py``: a denser check between a path's samples finds what the samples
step over, and the script runs an execution through its audit."""

from __future__ import annotations

from types import ModuleType

import pytest

from tests.conftest import ROOT, module_from_file, run_benchmark
from tests.executor.skills.test_pick_place import _kind, _picker_after_the_flight
from vlm_bench.executor.motion import arm_core as arm_core_module
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import arm_qpos


def _audit() -> ModuleType:
    return module_from_file("path_audit", ROOT / "benchmarks/path_audit.py")


def test_the_audit_finds_the_rim_between_coarse_checks(monkeypatch: pytest.MonkeyPatch) -> None:
    """color_distractor_green seed 2's incident scene: the way to above the green cube,
    sampled every 0.1 rad of its widest joint swing, is clear at every sample and passes a
    finger through the yellow basket; the audit's denser check finds the basket there."""
    episode, picker = _picker_after_the_flight("color_distractor_green", 2)
    with monkeypatch.context() as patch:
        patch.setattr(arm_core_module, "PATH_TRAVEL", 10.0)  # joint-space spacing alone
        coarse = picker.plan_grasp("green_cube", _kind(episode, "green_cube"))
        assert coarse is not None
        core = picker.hand.core
        now = arm_qpos(picker.loop.model, picker.loop.data)
        samples = [now, *core.joint_samples(now, coarse[0].q_start, coarse[0].shift)]
    query = CollisionQuery.of(set(), c.GRIPPER_OPEN, coarse[0].shift)
    assert core.hits_at(samples, query) == 0
    touched_between = _audit().touched_between
    touched, depth = touched_between(core, samples, query, 16)
    assert "yellow_basket" in touched
    assert depth > 0.0
    clear, none = touched_between(core, samples[:2], query, 16)
    assert (clear, none) == (set(), 0.0)


def test_the_audit_runs_an_execution() -> None:
    stdout = run_benchmark("path_audit.py", "--tasks", "clear_desk_push_box", "--workers", "1")
    assert "1 executions (seeds 3), 1 succeed" in stdout, stdout
    rows = [line for line in stdout.splitlines() if line.startswith("| ") and "clear" not in line]
    assert int(rows[0].strip("| ").split(" | ")[0]) > 0, stdout
