"""Prompts: Jinja2 templates over the skill library, few-shot examples, and the user turn."""

from vlm_bench.prompting.builder import (
    build_prompt,
    prompt_config_hash,
    render_system,
    render_text,
    shuffle_key,
)
from vlm_bench.prompting.examples import (
    LeakageFinding,
    check_no_leakage,
    few_shot_examples,
    find_leakage,
    select_examples,
)
from vlm_bench.prompting.replan import build_replan_prompt
from vlm_bench.prompting.skills_section import skill_rows, skills_digest, step_shape

__all__ = [
    "LeakageFinding",
    "build_prompt",
    "build_replan_prompt",
    "check_no_leakage",
    "few_shot_examples",
    "find_leakage",
    "prompt_config_hash",
    "render_system",
    "render_text",
    "select_examples",
    "shuffle_key",
    "skill_rows",
    "skills_digest",
    "step_shape",
]
