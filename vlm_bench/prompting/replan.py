"""The prompt of a closed loop's replan (docs/design.md#closed-loop): the same system message as
the first prompt (robot, skills, rules, examples: one rule source), and a user turn rendered
from ``prompts/replan.j2`` with the instruction, the steps executed so far with their outcome,
what the gripper holds, and the views (and scene text) of the state now.

A replan's hash covers the rendered text, the templates and the digest of the simulator state
the views show, so the response cache is keyed per round's request, and the hash is the same
whether the views were rendered or not (a planner that reads no images gets none).
``replan.j2`` is not one of the first prompt's templates: adding it left every open-loop
prompt hash as it was.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from functools import cache

from vlm_bench.prompting.builder import (
    _SLOT,
    _hash,
    _user_parts,
    object_order,
    render_system,
    rendered_pngs,
    scene_text,
    shuffle_key,
)
from vlm_bench.prompting.examples import select_examples
from vlm_bench.prompting.templates import render
from vlm_bench.resources import prompts_dir
from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.prompt import Prompt, PromptConfig

REPLAN_TEMPLATE = "replan.j2"
DETAIL_CHARS = 160
"""A failure detail is cut to this many characters (one line)."""


@cache
def _replan_digest() -> str:
    return hashlib.sha256((prompts_dir() / REPLAN_TEMPLATE).read_bytes()).hexdigest()


def _one_line(text: str | None) -> str:
    line = " ".join((text or "").split())
    return line if len(line) <= DETAIL_CHARS else line[: DETAIL_CHARS - 3] + "..."


def build_replan_prompt(
    episode: Episode,
    now: Episode,
    images: Mapping[str, object] | None,
    config: PromptConfig,
    feedback: Feedback,
    state: str,
) -> Prompt:
    """Render a replan's prompt.

    Args:
        episode: The episode (instruction, few-shot selection, object order).
        now: The episode as it stands now (its scene text is the state now).
        images: Views of the state now, by view name; None: not rendered (a planner that
            reads no images).
        config: The run's prompt options.
        feedback: The steps executed so far, what is held, whether only goals are unmet.
        state: Digest of the simulator state now
            (:func:`~vlm_bench.executor.live_state.state_digest`).
    """
    key = shuffle_key(episode) if config.few_shot_selection == "per_episode" else ""
    examples = select_examples(config.k_shot, config.few_shot_seed, key)
    system = render_system(config, examples)
    order = object_order(episode)
    steps = plan_to_json([s.step for s in feedback.executed])
    executed = [
        {"step": row, "status": s.status, "code": s.code, "detail": _one_line(s.detail)}
        for row, s in zip(steps, feedback.executed, strict=True)
    ]
    text = render(
        REPLAN_TEMPLATE,
        views=list(config.views),
        image=lambda view: _SLOT.format(view),
        object_ids=order if config.object_list else None,
        scene=scene_text(now, order) if config.scene_as_text else None,
        instruction=episode.instruction(config.instruction),
        executed=executed,
        held=feedback.held,
        incomplete=feedback.incomplete,
    )
    user = _user_parts(text)
    digest = hashlib.sha256(_hash(system, user).encode())
    digest.update(_replan_digest().encode())
    digest.update(state.encode())
    return Prompt(
        system=system,
        user=user,
        prompt_hash=digest.hexdigest(),
        example_ids=tuple(ex.id for ex in examples),
        object_order=tuple(order),
        images=rendered_pngs(images, config.views),
    )
