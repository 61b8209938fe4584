"""The replan prompt: same system message as the first prompt, feedback on executed steps, the
state now, a hash per round's request; golden snapshot."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

from tests.conftest import module_from_file
from vlm_bench.prompting import build_prompt, build_replan_prompt, render_text
from vlm_bench.types.closed_loop import ExecutedStep, Feedback
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.prompt import PromptConfig


def _builder_tests() -> ModuleType:
    """The first prompt's tests (their synthetic episode, images and golden check)."""
    return module_from_file(
        "_prompt_builder_tests", Path(__file__).with_name("test_prompt_builder.py")
    )


_shared = _builder_tests()
IMAGES, _check_golden, _episode = _shared.IMAGES, _shared._check_golden, _shared._episode
MOVE = UavStep(direction=Direction.FRONTLEFT)
PICK = ArmStep(object="gray_cube", skill="pick")
PLACE = ArmStep(object="yellow_basket", skill="place")
FAILED = Feedback(
    round=1,
    executed=(
        ExecutedStep(step=MOVE, status="done"),
        ExecutedStep(step=PICK, status="done"),
        ExecutedStep(
            step=PLACE, status="failed", code="slipped", detail="gray_cube slipped\nfrom it"
        ),
    ),
    held=None,
)
INCOMPLETE = Feedback(
    round=2,
    executed=tuple(ExecutedStep(step=s, status="done") for s in (MOVE, PICK, PLACE)),
    held=None,
    incomplete=True,
)
STATE = "0" * 64  # a state digest


def test_golden_replan_prompt() -> None:
    config = PromptConfig(scene_as_text=True)
    prompt = build_replan_prompt(_episode(), _episode(), IMAGES, config, FAILED, STATE)
    _check_golden("replan_default.txt", render_text(prompt))


def test_replan_keeps_the_first_prompts_system_message_and_rules() -> None:
    config = PromptConfig()
    first = build_prompt(_episode(), IMAGES, config)
    replan = build_replan_prompt(_episode(), _episode(), IMAGES, config, FAILED, STATE)
    assert replan.system == first.system and replan.views() == first.views()
    text = render_text(replan)
    assert '"skill": "place"}: failed (slipped): gray_cube slipped from it' in text
    assert "The gripper holds: nothing." in text and "not complete" not in text


def test_unmet_goals_are_reported_without_naming_them() -> None:
    replan = build_replan_prompt(_episode(), _episode(), IMAGES, PromptConfig(), INCOMPLETE, STATE)
    user = render_text(replan).split("### user", 1)[1]
    assert "Every step succeeded, but the task is not complete." in user
    assert "inside" not in user and "goal" not in user


def test_the_hash_covers_the_feedback_and_the_state_not_the_pixels() -> None:
    config = PromptConfig()
    base = build_replan_prompt(_episode(), _episode(), IMAGES, config, FAILED, STATE)
    other = build_replan_prompt(_episode(), _episode(), IMAGES, config, INCOMPLETE, STATE)
    moved = build_replan_prompt(_episode(), _episode(), IMAGES, config, FAILED, "1" * 64)
    first = build_prompt(_episode(), IMAGES, config)
    hashes = {base.prompt_hash, other.prompt_hash, moved.prompt_hash, first.prompt_hash}
    assert len(hashes) == 4
    unrendered = build_replan_prompt(_episode(), _episode(), None, config, FAILED, STATE)
    assert unrendered.prompt_hash == base.prompt_hash
    assert render_text(unrendered) == render_text(base)


def test_views_not_rendered_leave_the_request_without_images() -> None:
    config = PromptConfig(scene_as_text=True)
    shown = build_prompt(_episode(), IMAGES, config)
    blind = build_prompt(_episode(), None, config)
    assert blind.prompt_hash == shown.prompt_hash and blind.images == {}
    assert render_text(blind) == render_text(shown)
    request = blind.to_request("r")
    assert request.images() == [] and len(shown.to_request("r").images()) == len(IMAGES)
    texts = [p for p in shown.to_request("r").user if p.type == "text"]
    assert [p for p in request.user if p.type == "text"] == texts
