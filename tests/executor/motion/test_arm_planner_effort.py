"""The planner's shortcuts change no plan: contacts are counted only as far as they can still
matter, and the loop records a contact list it saw the step before only once per call to
``take_collisions``."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import pytest
from incidents import incident_episode

from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.motion.arm_core import ArmCore
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionChecker, CollisionQuery
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import PlanExecution
from vlm_bench.sim import constants as c
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.sim.scene import build_scene
from vlm_bench.types.base import FloatArray


def test_counting_contacts_up_to_a_limit_stops_at_the_first_posture_over_it(
    sideways_hand: Hand, monkeypatch: pytest.MonkeyPatch
) -> None:
    hand = sideways_hand
    out = arm_qpos(hand.loop.model, hand.loop.data)  # the arm put out sideways
    query = CollisionQuery.of(set(), c.GRIPPER_OPEN, BaseMove.still())
    stowed = np.asarray(c.ARM_STOW)
    calls: list[int] = []
    checks = CollisionChecker.collisions

    def counted(self: CollisionChecker, *args: object) -> list[int]:
        calls.append(1)
        return checks(self, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(CollisionChecker, "collisions", counted)
    full = hand.core.path_hits(out, stowed, query)
    full_checks = len(calls)
    calls.clear()
    anyhit = hand.core.path_hits(out, stowed, query, limit=0)
    assert full > 1
    assert 0 < anyhit <= full
    assert len(calls) < full_checks  # it stopped where the count went over
    assert hand.core.path_hits(out, stowed, query, limit=full) == full
    assert hand.core.path_hits(out, stowed, query, limit=full - 1) == full


@pytest.mark.slow  # a whole episode twice (~30 s); the pruning's unit test above stays default
def test_pruned_planning_executes_as_full_counting_does(monkeypatch: pytest.MonkeyPatch) -> None:
    """standard_pick_place seed 9: the release is planned over ~800 candidates, most of them
    with contacts; counting every contact of every candidate executes the same episode (an
    off-by-one in the pruning changes its simulated time)."""
    episode = incident_episode("standard_pick_place", 9)

    def execute() -> dict[str, object]:
        return execute_plan(episode, episode.gt_plan).model_dump(exclude={"wall_time_s"})

    pruned = execute()
    hits_at = ArmCore.hits_at

    def every_contact(
        self: ArmCore, postures: Iterable[FloatArray], query: CollisionQuery, limit: float = 0
    ) -> int:
        return hits_at(self, postures, query)

    monkeypatch.setattr(ArmCore, "hits_at", every_contact)
    assert execute() == pruned


def test_a_contact_that_lasts_is_reported_again_after_each_take() -> None:
    """Fingers closed on the held object touch it at every step; each call to
    ``take_collisions`` after a control step reports it, not only the first."""
    episode = get_episode("standard_pick_place", 0)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for index in range(2):  # fly there, pick
        assert execution.step(index, episode.gt_plan[index], episode.gt_plan).status == "ok"
    held = loop.held
    assert held is not None
    loop.take_collisions()
    takes = []
    for _ in range(3):
        loop.control_step()
        takes.append(loop.take_collisions())
    assert all(any(name.startswith(held) for name in take) for take in takes), takes
