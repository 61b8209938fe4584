"""The planning rules every UAV move of the benchmark follows, in one place.

The GT builder (:mod:`vlm_bench.episodes.gt_builder`), the prompt's rule section
(:mod:`vlm_bench.prompting`), the few-shot examples, the ``rules`` planner and the executor's
stopping rule all read them from here: where an ARM step works (its working point), when a
working point is in reach, which of the eight directions a move takes, where a move stops, when
and in which order the UAV climbs or descends, and how the scene changes after each skill.
"""

from vlm_bench.rules.approach import UavState, WorkPoint, ambiguity, approach_moves
from vlm_bench.rules.frame import body_bearing_deg, move_stop, quantise_bearing, rotate_xy, wrap_deg
from vlm_bench.rules.replan import remaining_arm_steps
from vlm_bench.rules.scene_plan import plan_from_scene, plan_segments
from vlm_bench.rules.scene_text import SceneEntry, format_scene, parse_scene, scene_entries
from vlm_bench.rules.work import (
    DRAWER_FLOOR_BELOW_HANDLE,
    DRAWER_INSIDE_BEHIND_HANDLE,
    DRAWER_PULL,
    rule_numbers,
)

__all__ = [
    "DRAWER_FLOOR_BELOW_HANDLE",
    "DRAWER_INSIDE_BEHIND_HANDLE",
    "DRAWER_PULL",
    "SceneEntry",
    "UavState",
    "WorkPoint",
    "ambiguity",
    "approach_moves",
    "body_bearing_deg",
    "format_scene",
    "move_stop",
    "parse_scene",
    "plan_from_scene",
    "plan_segments",
    "quantise_bearing",
    "remaining_arm_steps",
    "rotate_xy",
    "rule_numbers",
    "scene_entries",
    "wrap_deg",
]
