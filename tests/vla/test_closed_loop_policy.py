"""A hierarchical closed loop: a policy's timeout fails its ARM step, the planner replans from
the state it left with the failure in its feedback, in the same simulation."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.vla import VlaAction, policy_skills, run_closed_loop
from vlm_bench.vla.observation import VlaObservation

PICK = ArmStep(object="gray_cube", skill="pick")
HOP = UavStep(direction=Direction.UP, distance=0.1)


def test_a_policy_timeout_triggers_a_replan_from_where_it_stopped() -> None:
    episode = get_episode("standard_pick_place", 0)
    seen: list[tuple[Episode, Feedback | None]] = []

    def planner(now: Episode, feedback: Feedback | None) -> list[UavStep | ArmStep]:
        seen.append((now, feedback))
        return [PICK] if feedback is None else ([HOP] if len(seen) == 2 else [])

    def hold(observation: VlaObservation, step: ArmStep) -> VlaAction:
        return VlaAction.holding(observation.proprio)  # never ends the step

    skills = policy_skills(hold, max_steps=4, views=())
    result = run_closed_loop(episode, planner, arm_skills=skills, max_rounds=3)
    assert len(result.results) == 2 and result.success_round is None
    first = result.feedback[0]
    assert [s.status for s in first.executed] == ["failed"]
    assert first.executed[0].code == "policy_timeout" and not first.incomplete
    assert seen[1][1] == first and seen[2][1] is not None  # the third call ends it (no steps)
    # the second round continued the simulation: the UAV is where the hop left it
    z0 = result.results[0].final_uav_pose.pos[2]
    assert result.results[1].final_uav_pose.pos[2] > z0 + 0.05
    assert abs(seen[1][0].uav_start.pos[2] - z0) < 0.01  # the planner saw the state now


def test_the_documented_closed_loop_example_runs(capsys: pytest.CaptureFixture[str]) -> None:
    docs = Path(__file__).resolve().parents[2] / "docs" / "hierarchical.md"
    text = docs.read_text()
    policy = re.findall(r"```python\n(.*?)```", text, re.S)[0]
    (loop,) = re.findall(r"```py\n(.*?)```", text, re.S)
    namespace: dict[str, object] = {"__name__": "docs_example"}
    exec(compile(policy, str(docs), "exec"), namespace)
    exec(compile(loop, str(docs), "exec"), namespace)
    out = capsys.readouterr().out
    assert "replan after [('UAV', 'done', None), ('ARM', 'failed', 'policy_timeout')]" in out
    assert "None ['policy_timeout']" in out
