"""The request a run sends for one episode, built in one place for runs and for
``vlm-bench prompt`` (:func:`preview_request`), so that a preview shows what a run sends."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from vlm_bench.episodes import get_episode
from vlm_bench.parsing import plan_json_schema
from vlm_bench.prompting import build_prompt, render_text
from vlm_bench.runner.cached_snapshots import SnapshotSource, check_resolution
from vlm_bench.runner.selection import EpisodeRef, select_episodes
from vlm_bench.storage import SnapshotCache
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import GenerationRequest, RequestMeta
from vlm_bench.types.prompt import Prompt, PromptConfig
from vlm_bench.types.run import RunConfig


def episode_request(
    config: RunConfig, ref: EpisodeRef, episode: Episode, images: Mapping[str, bytes] | None
) -> tuple[Prompt, GenerationRequest]:
    """The prompt of one episode under the run's options, and the backend request made of it.

    Args:
        config: The run configuration (prompt options, constrained decoding).
        ref: The episode and instruction variant.
        episode: The episode ``ref`` names.
        images: PNG bytes by view (the views the config shows); None: not rendered, for a
            planner that reads no images.
    """
    options = config.prompt_config(ref.variant)
    return prompt_request(ref, episode, images, options, config.generation.constrained)


def prompt_request(
    ref: EpisodeRef,
    episode: Episode,
    images: Mapping[str, bytes] | None,
    options: PromptConfig,
    constrained: bool,
) -> tuple[Prompt, GenerationRequest]:
    """:func:`episode_request` under resolved options: ``ref.variant``'s prompt options, and
    whether the request carries the plan's JSON schema."""
    prompt = build_prompt(episode, images, options)
    object_ids = episode.object_ids()
    request = prompt.to_request(
        ref.key,
        episode_id=ref.key,
        meta=RequestMeta(
            task_id=ref.task_id,
            seed=ref.seed,
            gt_plan=episode.gt_plan,
            arm_steps=tuple(episode.arm_steps()),
            object_ids=tuple(object_ids),
        ),
        json_schema=plan_json_schema(object_ids) if constrained else None,
    )
    return prompt, request


def run_snapshots(config: RunConfig, cache: SnapshotCache | None) -> SnapshotSource:
    """The snapshot source of a run: the views it shows (none with ``images`` off), at its
    resolution, labelled as it asks."""
    views = config.views if config.images else ()
    return SnapshotSource(views, config.resolution, config.labels, cache)


@dataclass(frozen=True)
class PromptPreview:
    """What a run with these options sends for one episode."""

    prompt: Prompt
    """The rendered prompt (its hash is the one the run's record stores)."""
    request: GenerationRequest
    """The backend request: system text, the user turn with the images, the output schema."""

    def text(self) -> str:
        """System and user turns with ``<image:view>`` where each image goes."""
        return render_text(self.prompt)

    def write_images(self, folder: Path) -> list[Path]:
        """Write the request's images as ``<view>.png`` into ``folder`` (created); returns
        the paths in prompt order."""
        folder.mkdir(parents=True, exist_ok=True)
        paths = []
        for image in self.request.images():
            path = folder / f"{image.view}.png"
            path.write_bytes(image.png)
            paths.append(path)
        return paths


def preview_request(config: RunConfig, snapshot_cache: Path | None = None) -> PromptPreview:
    """The request a run of ``config`` sends for its first episode (one task, seed and
    instruction variant is what a preview asks for).

    Args:
        config: The run configuration.
        snapshot_cache: The shared PNG cache folder, or None to render.

    Raises:
        UnknownNameError: An unknown task id. ConfigError: A resolution the simulator cannot
            render, or more few-shot examples than there are.
    """
    check_resolution(config.resolution)
    ref = select_episodes(config)[0]
    episode = get_episode(ref.task_id, ref.seed)
    cache = SnapshotCache(snapshot_cache) if snapshot_cache is not None else None
    source = run_snapshots(config, cache)
    try:
        prompt, request = episode_request(config, ref, episode, source.images(episode))
    finally:
        source.close()
    return PromptPreview(prompt, request)
