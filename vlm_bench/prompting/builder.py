"""Build a prompt for an episode: system text, user turn with image slots, and its hash."""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Mapping, Sequence

from vlm_bench.errors import ConfigError
from vlm_bench.prompting.examples import example_plan, example_scene_text, select_examples
from vlm_bench.prompting.skills_section import skill_rows, skills_digest
from vlm_bench.prompting.templates import render, templates_digest
from vlm_bench.rules import format_scene, rule_numbers, scene_entries
from vlm_bench.storage.png import to_png
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import TextPart
from vlm_bench.types.plan import Direction, plan_to_json
from vlm_bench.types.prompt import (
    FewShotExample,
    ImageSlot,
    Prompt,
    PromptConfig,
    PromptPart,
)

# NUL cannot occur in instructions or ids, so these markers cannot be forged by data.
_SLOT = "\x00image:{}\x00"
_SLOT_RE = re.compile("\x00image:([a-z]+)\x00")


def shuffle_key(episode: Episode) -> str:
    """``task_id:seed``: seeds an episode's few-shot selection and object order, the same for
    both instruction variants (a run's record key is
    :func:`~vlm_bench.types.records.episode_key`, one per variant)."""
    return f"{episode.task_id}:{episode.seed}"


def render_system(config: PromptConfig, examples: Sequence[FewShotExample] = ()) -> str:
    """The system message: robot, views, skill library, the movement rules (their numbers
    from :func:`~vlm_bench.rules.rule_numbers`, the GT's own), output format, examples."""
    shots = ""
    if examples:
        shots = render(
            "few_shot.j2",
            examples=[
                {
                    "id": ex.id,
                    "setting": ex.setting,
                    "scene": example_scene_text(ex),
                    "instruction": ex.instruction,
                    "plan": plan_to_json(example_plan(ex)),
                }
                for ex in examples
            ],
            scene_as_text=config.scene_as_text,
        ).strip()
    return render(
        "system.j2",
        directions=[d.value for d in Direction],
        views=list(config.views),
        skills=skill_rows(),
        object_list=config.object_list,
        scene_as_text=config.scene_as_text,
        rules=rule_numbers(),
        examples=shots,
    )


def _rank(key: str, item: str) -> bytes:
    return hashlib.sha256(f"objects|{key}|{item}".encode()).digest()


def object_order(episode: Episode) -> list[str]:
    """The episode's object and part ids in a seeded shuffled order (the same for both
    instruction variants): the target comes first only as often as chance gives."""
    key = shuffle_key(episode)
    return sorted(episode.object_ids(), key=lambda item: _rank(key, item))


def scene_text(episode: Episode, order: Sequence[str]) -> str:
    """The scene as text (``--scene-as-text``): every object and part in the body frame at the
    start, listed in ``order``."""
    rank = {item: i for i, item in enumerate(order)}
    entries = sorted(scene_entries(episode), key=lambda e: rank.get(e.id, len(rank)))
    return format_scene(entries, episode.uav_start.pos[2])


def _user_parts(text: str) -> tuple[PromptPart, ...]:
    parts: list[PromptPart] = []
    pos = 0
    for match in _SLOT_RE.finditer(text):
        before = text[pos : match.start()]
        if before.strip():
            parts.append(TextPart(text=before.strip("\n")))
        parts.append(ImageSlot.model_validate({"view": match.group(1)}))
        pos = match.end()
    rest = text[pos:]
    if rest.strip():
        parts.append(TextPart(text=rest.strip("\n")))
    return tuple(parts)


def _hash(system: str, user: Sequence[PromptPart]) -> str:
    payload = {
        "system": system,
        "user": [p.model_dump(mode="json") for p in user],
        "templates": templates_digest(),
        "skills": skills_digest(),
    }
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


def build_prompt(
    episode: Episode, images: Mapping[str, object] | None, config: PromptConfig | None = None
) -> Prompt:
    """Render the prompt of one episode.

    Args:
        episode: The episode (instructions, objects and parts give the object-id list).
        images: Snapshots by view name (PNG bytes, PIL images or uint8 arrays). Views the
            config leaves out are ignored. None: not rendered, for a planner that reads no
            images (the user turn keeps its image slots; the request carries no images).
        config: Prompt options (views, k-shot, object list, instruction variant).

    Returns:
        The prompt, with the configured views' images as PNG bytes.

    Raises:
        ConfigError: An image for a configured view is missing or not an image, or k_shot
            exceeds the number of few-shot examples.
    """
    config = config or PromptConfig()
    given = images if images is not None else dict.fromkeys(config.views)
    missing = [v for v in config.views if v not in given]
    if missing:
        raise ConfigError(
            f"no image for view(s) {', '.join(missing)}; given: {', '.join(given) or 'none'}"
        )
    key = shuffle_key(episode) if config.few_shot_selection == "per_episode" else ""
    examples = select_examples(config.k_shot, config.few_shot_seed, key)
    system = render_system(config, examples)
    order = object_order(episode)
    text = render(
        "user.j2",
        views=list(config.views),
        image=lambda view: _SLOT.format(view),
        object_ids=order if config.object_list else None,
        scene=scene_text(episode, order) if config.scene_as_text else None,
        altitude=episode.uav_start.pos[2],
        instruction=episode.instruction(config.instruction),
    )
    user = _user_parts(text)
    pngs = rendered_pngs(images, config.views)
    return Prompt(
        system=system,
        user=user,
        prompt_hash=_hash(system, user),
        example_ids=tuple(ex.id for ex in examples),
        object_order=tuple(order),
        images=pngs,
    )


def rendered_pngs(images: Mapping[str, object] | None, views: Sequence[str]) -> dict[str, bytes]:
    """PNG bytes of ``views`` (none where the views were not rendered: ``images`` None)."""
    return {} if images is None else {v: to_png(images[v]) for v in views}


def user_text(prompt: Prompt) -> str:
    """The user turn as one text: its text parts, and ``<image:view>`` on its own line where
    each image goes (what ``vlm-bench prompt`` prints and the exported dataset holds)."""
    return "\n".join(
        f"<image:{p.view}>" if isinstance(p, ImageSlot) else p.text for p in prompt.user
    )


def render_text(prompt: Prompt) -> str:
    """A readable rendering with ``<image:view>`` placeholders (golden files, HTML gallery)."""
    user = user_text(prompt)
    return f"### system\n{prompt.system.rstrip()}\n\n### user\n{user.rstrip()}\n"


def prompt_config_hash(config: PromptConfig) -> str:
    """sha256 of everything that shapes a run's prompts: templates, examples, skills, config.

    For the run manifest: two runs with equal hashes render identical prompts for an episode.
    """
    payload = f"{templates_digest()}|{skills_digest()}|{config.model_dump_json()}"
    return hashlib.sha256(payload.encode()).hexdigest()
