"""The hand rises over a place's destination only where its straight line touches nothing; else
the UAV climbs, carrying it (docs/decisions.md, "A place's lift is checked like any move")."""

from __future__ import annotations

from vlm_bench.episodes import get_episode
from vlm_bench.executor import SimLoop, execute_plan
from vlm_bench.sim.constants import part_joint


def test_the_lift_over_an_open_drawer_does_not_push_it_shut() -> None:
    # The pick leaves the cube 0.75 m under the arm base beside the open drawer; the straight
    # 0.54 m line up to the release swung the elbow into the drawer's front and pushed it from
    # 0.35 m open to 0.18 m, under the release already chosen, so every way down met the front.
    episode = get_episode("store_and_close", 9)
    place = next(i for i, s in enumerate(episode.gt_plan) if getattr(s, "skill", "") == "place")
    openings: list[float] = []

    def watch(loop: SimLoop) -> None:
        joint = loop.model.joint(part_joint("top_drawer"))
        openings.append(float(loop.data.qpos[joint.qposadr[0]]))

    result = execute_plan(episode, episode.gt_plan[: place + 1], observers=[watch])
    assert result.steps_ok, result.failure_reason
    assert min(openings) > 0.34  # opened 0.35 m by the scene
    inside = [g.predicate == "inside" for g in episode.goals].index(True)
    assert result.goals[inside], "the cube is not in the drawer"
