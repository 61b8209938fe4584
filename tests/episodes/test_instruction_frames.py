"""Viewpoint words in instructions declare their frame, and the frame picks the GT referent.

The prompt tells the model that left/right/front/back are the UAV's own body-frame directions,
while the ground truth resolves an instruction's "left"/"right" in the world frame as seen in
the overhead camera view (image right = world +x, image up = world +y). An instruction that
uses a viewpoint-dependent word must therefore say so with ``FRAME_PHRASE`` (one phrase, so a
prompt can explain it once) or be rewritten without the word.

Viewpoint-dependent (need the frame):
- left/right and their variants, front/back/behind, forward/backward/ahead: they change with
  the viewer's heading, and left/right/front/back are also UAV move directions in the prompt.
  They are flagged in every sense ("somebody left", "right at the top"): a bare one is a word
  the model may read as a body-frame direction, so such phrasing is rewritten instead.
- clockwise and its opposites: they flip with the side the knob is seen from.
- near/far words (nearest, closest, farthest, ...) unless anchored to an object ("closest to
  the basket", "near the plate"): unanchored they mean near/far from the viewer.

Viewer-independent (no frame needed): relations to another object ("next to", "beside", "by",
"between", "inside", "on top of", "onto", "near the X"), vertical words defined by gravity
("top/middle/bottom drawer", "highest", "upright", "up", "down"), and sub-words of longer
words ("leftover", "upright", "rightly"): the regexes match whole words only.
"""

from __future__ import annotations

import re

import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes.layout import POS_JITTER
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant, TaskSpec

FRAME_PHRASE = "as seen in the overhead view"

_DIRECTIONAL = re.compile(
    r"\b("
    r"left-hand|right-hand|lefthand|righthand|leftmost|rightmost|left|right"
    r"|frontmost|front|foreground|backmost|background|backwards?|back|behind|forwards?|ahead"
    r"|counter-?clockwise|anti-?clockwise|clockwise"
    r")\b",
    re.IGNORECASE,
)
# Near/far words; ok when followed by an object anchor: "[to|from] the <object>", optionally
# after one word ("the closest cup to the basket"); the UAV/robot/camera are no anchor.
_DISTANCE = re.compile(
    r"\b(nearest|nearer|nearby|near|closest|closer|farthest|farther|furthest|further|far)\b"
    r"(?!\s+(?:(?:\w+\s+)?(?:to|from)\s+)?(?:the|a|an)\s+"
    r"(?!(?:uav|drone|robot|camera|viewer)\b)\w)",
    re.IGNORECASE,
)
_LATERAL = re.compile(r"\b(left|right)(?:-hand|hand|most)?\b", re.IGNORECASE)

TASKS = all_tasks()
CASES = [(t, v) for t in TASKS for v in INSTRUCTION_VARIANTS]
CASE_IDS = [f"{t.id}-{v}" for t, v in CASES]

# Tasks whose instructions pick one of two same-kind objects by "left"/"right":
# task id -> (word, id the instruction means, the other candidate). The meant id is an object
# of the task's ARM steps and lies at the smaller (left) / larger (right) world x.
LATERAL_REFERENTS: dict[str, tuple[tuple[str, str, str], ...]] = {
    "pick_left_cup_red": (("left", "red_cup_2", "red_cup_1"),),
    "pick_left_box_white": (
        ("left", "white_box_1", "white_box_2"),
        ("left", "yellow_basket_2", "yellow_basket_1"),
    ),
    "cross_color_sorting": (
        ("left", "red_plate", "black_plate"),
        ("right", "black_plate", "red_plate"),
    ),
    "category_sorting": (("right", "gray_basket_1", "gray_basket_2"),),
}
# Jitter moves each object up to POS_JITTER in x; a wider gap keeps left/right in every seed.
MIN_X_GAP = 2 * POS_JITTER + 0.05


def viewpoint_words(text: str) -> list[str]:
    """Viewpoint-dependent words of ``text`` (lower case, in order of appearance)."""
    hits = [*_DIRECTIONAL.finditer(text), *_DISTANCE.finditer(text)]
    return [m.group(1).lower() for m in sorted(hits, key=lambda m: m.start())]


def _text(task: TaskSpec, variant: InstructionVariant) -> str:
    return str(getattr(task.instructions, variant))


def _x(task: TaskSpec, obj_id: str) -> float:
    (obj,) = [o for o in task.objects if o.id == obj_id]
    return obj.xy[0]


@pytest.mark.parametrize(
    "text",
    [
        "Pick up the red cup on the left and place it on the red plate.",
        "Put it in the left-hand basket.",
        "The pair on the right stays as it is.",
        "Take the rightmost box.",
        "Push the cube to the back of the table.",
        "Put the mug behind the bowl.",
        "Place it in front of the cabinet.",
        "Turn the knob clockwise.",
        "Turn the knob anti-clockwise.",
        "Pick up the nearest cup.",
        "Use the basket closer to you.",
        "Put it in the far basket.",
        "Grab the closest cup to the UAV.",
        "Somebody left a spare part on the bench.",
        "The drawer right at the top of the cabinet.",
    ],
)
def test_detector_flags_viewpoint_words(text: str) -> None:
    assert viewpoint_words(text), text


@pytest.mark.parametrize(
    "text",
    [
        "Put that leftover piece of lumber away in the purple storage box.",
        "Place the meat can upright on the white plate.",
        "She rightly put the bolt in the bowl.",
        "Push the blue cube next to the gray basket.",
        "Leave it beside the basket, by the yellow one.",
        "The yellow mug stands between the two plates.",
        "Stack the camera on top of the LiDAR, then drop the cube inside the bowl.",
        "Open the drawer that sits between the top and bottom ones.",
        "Could you open the highest drawer in that cabinet?",
        "Put the cube near the basket.",
        "Pick up the cup closest to the red plate.",
        "Take the cube farther from the bowl.",
        "Pick up the red cup closest to the plate, then close the drawer.",
    ],
)
def test_detector_ignores_viewer_independent_words(text: str) -> None:
    assert viewpoint_words(text) == [], text


@pytest.mark.parametrize(("task", "variant"), CASES, ids=CASE_IDS)
def test_viewpoint_words_declare_the_frame(task: TaskSpec, variant: InstructionVariant) -> None:
    text = _text(task, variant)
    words = viewpoint_words(text)
    assert not words or FRAME_PHRASE in text.lower(), (
        f"{task.id} ({variant}): viewpoint word(s) {words} without the frame "
        f"{FRAME_PHRASE!r}; add it, anchor near/far words to an object, or rewrite: {text!r}"
    )


@pytest.mark.parametrize(("task", "variant"), CASES, ids=CASE_IDS)
def test_frame_phrase_only_with_viewpoint_words(
    task: TaskSpec, variant: InstructionVariant
) -> None:
    text = _text(task, variant)
    if FRAME_PHRASE in text.lower():
        assert viewpoint_words(text), f"{task.id} ({variant}): frame with nothing to frame"


def test_lateral_referent_table_covers_every_left_right_task() -> None:
    lateral = {t.id for t, v in CASES if _LATERAL.search(_text(t, v))}
    assert lateral == set(LATERAL_REFERENTS), (
        "tasks using left/right must be listed in LATERAL_REFERENTS (and only those): "
        f"missing {sorted(lateral - set(LATERAL_REFERENTS))}, "
        f"extra {sorted(set(LATERAL_REFERENTS) - lateral)}"
    )


@pytest.mark.parametrize("task_id", sorted(LATERAL_REFERENTS))
def test_left_right_referent_matches_world_x(task_id: str) -> None:
    (task,) = [t for t in TASKS if t.id == task_id]
    kinds = {o.id: o.kind for o in task.objects}
    arm_objects = {s.object for s in task.arm_steps}
    for word, meant, other in LATERAL_REFERENTS[task_id]:
        for variant in INSTRUCTION_VARIANTS:
            said = {m.group(1).lower() for m in _LATERAL.finditer(_text(task, variant))}
            assert word in said, f"{task_id} ({variant}): no {word!r} in the instruction"
        assert meant in arm_objects, f"{task_id}: {meant!r} is no ARM-step object"
        assert other in kinds and kinds[other] == kinds[meant], (
            f"{task_id}: {other!r} is not a {kinds[meant]} like {meant!r}"
        )
        gap = _x(task, other) - _x(task, meant)
        side = "right"
        if word == "right":
            gap, side = -gap, "left"
        assert gap >= MIN_X_GAP, (
            f"{task_id}: {word!r} means {meant!r} (x={_x(task, meant):+.2f}), but {other!r} "
            f"(x={_x(task, other):+.2f}) is not clearly to its {side} in the world/overhead "
            f"frame (need a gap of {MIN_X_GAP:.2f} m)"
        )


_DESCRIBED = re.compile(r"\bThe (left|right) ([a-z ]+?) is ([a-z][a-z0-9_]*)\b")


@pytest.mark.parametrize("task_id", sorted(LATERAL_REFERENTS))
def test_description_names_the_same_referent(task_id: str) -> None:
    """'The left cup is red_cup_2' in a description agrees with the referent table."""
    (task,) = [t for t in TASKS if t.id == task_id]
    table = {(word, meant) for word, meant, _ in LATERAL_REFERENTS[task_id]}
    for word, _, obj_id in _DESCRIBED.findall(task.description):
        assert (word, obj_id) in table, f"{task_id}: description says the {word} one is {obj_id}"
