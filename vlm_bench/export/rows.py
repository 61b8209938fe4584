"""The rows of an export (:class:`~vlm_bench.export.row_model.DatasetRow`, one per episode),
built by the run's own request code: what a run with the same options sends, byte for byte.

Other exports (dataset, SFT, demos) and harness tasks iterate :func:`iter_rows`.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

from vlm_bench.episodes import get_episode
from vlm_bench.export.options import ExportOptions
from vlm_bench.export.row_model import DatasetRow, GtStep
from vlm_bench.prompting.builder import user_text
from vlm_bench.runner.cached_snapshots import check_resolution
from vlm_bench.runner.episode_request import episode_request, run_snapshots
from vlm_bench.runner.selection import EpisodeRef, select_episodes
from vlm_bench.storage import SnapshotCache
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION
from vlm_bench.types.episode import Episode
from vlm_bench.types.generation import GenerationRequest
from vlm_bench.types.plan import plan_to_json
from vlm_bench.types.prompt import Prompt


def row_of(
    ref: EpisodeRef, episode: Episode, prompt: Prompt, request: GenerationRequest
) -> DatasetRow:
    """The dataset row of one episode's prompt and request."""
    plan = plan_to_json(episode.gt_plan)
    return DatasetRow(
        key=ref.key,
        benchmark_version=BENCHMARK_VERSION,
        task_id=episode.task_id,
        suite=episode.suite.value,
        seed=episode.seed,
        instruction=ref.variant,
        instruction_text=episode.instruction(ref.variant),
        system=request.system,
        user=user_text(prompt),
        views=tuple(prompt.views()),
        images={image.view: image.png for image in request.images()},
        objects=tuple(episode.object_ids()),
        gt_plan=json.dumps(plan),
        gt_steps=tuple(GtStep.model_validate(step) for step in plan),
        prompt_hash=prompt.prompt_hash,
        example_ids=prompt.example_ids,
    )


def episode_refs(options: ExportOptions) -> list[EpisodeRef]:
    """The episodes an export holds, in benchmark order (validates the options).

    Raises:
        ConfigError: An invalid option or a resolution the simulator cannot render.
            UnknownNameError: An unknown task id.
    """
    config = options.run_config()
    check_resolution(config.resolution)
    return select_episodes(config)


def iter_rows(options: ExportOptions, snapshot_cache: Path | None = None) -> Iterator[DatasetRow]:
    """The rows of an export, one at a time (memory stays bounded), in benchmark order.

    Args:
        options: Episode selection and prompt options.
        snapshot_cache: The shared PNG cache folder runs use, or None to render.

    Raises:
        ConfigError / UnknownNameError: As :func:`episode_refs`, before any row is built.
    """
    refs = episode_refs(options)
    config = options.run_config()
    cache = SnapshotCache(snapshot_cache) if snapshot_cache is not None else None
    source = run_snapshots(config, cache)
    try:
        for ref in refs:
            episode = get_episode(ref.task_id, ref.seed)
            prompt, request = episode_request(config, ref, episode, source.images(episode))
            yield row_of(ref, episode, prompt, request)
    finally:
        source.close()
