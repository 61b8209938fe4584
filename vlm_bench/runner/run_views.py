"""The views of a run's episodes that its folder does not keep, for the report's gallery
(:class:`~vlm_bench.report.gallery_views.ViewSource`): reports read run folders only, so whoever
asks for a gallery (the CLI's ``report``) passes these in.

An episode's start views come from the shared snapshot cache (``.snapshots`` beside the run
folder, or ``VLM_BENCH_SNAPSHOT_CACHE``), keyed as the run keyed them (episode, resolution,
labels), so they are the pixels the model saw; views missing there (a run shown fewer views, a
cache deleted) are rendered when allowed. A replan's views are in no file: they are rendered by
executing the episode's earlier rounds (the simulation is deterministic, so these too are the
pixels the model saw), only when rendering is allowed.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunManifest

if TYPE_CHECKING:
    from vlm_bench.runner.cached_snapshots import SnapshotSource


class RunViews:
    """PNG views of one run's episodes: from the snapshot cache, rendered if ``render``."""

    def __init__(self, run_dir: Path, manifest: RunManifest, render: bool) -> None:
        from vlm_bench.storage import SnapshotCache, default_snapshot_cache

        self.config = manifest.config
        self.cache = SnapshotCache(default_snapshot_cache(run_dir.resolve()))
        self.render = render
        self.rendered = 0
        self._source: SnapshotSource | None = None

    def start_views(self, task_id: str, seed: int) -> dict[str, bytes]:
        """The views of the episode's start found (all four when rendering is allowed)."""
        from vlm_bench.episodes import get_episode
        from vlm_bench.runner.cached_snapshots import SnapshotSource, snapshot_key

        size, labels = self.config.resolution, self.config.labels
        episode = get_episode(task_id, seed)
        key = snapshot_key(episode, size, labels)
        pngs: dict[str, bytes] = {
            v: png for v in VIEWS if (png := self.cache.get(key, v)) is not None
        }
        if len(pngs) < len(VIEWS) and self.render:
            if self._source is None:
                self._source = SnapshotSource(VIEWS, size, labels, self.cache)
            pngs = self._source.images(episode)
            self.rendered += 1
        return pngs

    def round_views(self, record: EpisodeRecord, round_index: int) -> dict[str, bytes]:
        """The views replan ``round_index`` of ``record`` saw; none when rendering is not
        allowed or the record has no such round."""
        from vlm_bench.episodes import get_episode
        from vlm_bench.parsing import parse_plan
        from vlm_bench.rounds.state import StateView
        from vlm_bench.runner.execution_jobs import ExecutionJob, execute_job
        from vlm_bench.runner.plan_executor import record_plan

        first = record_plan(record)
        if not self.render or first is None or record.rounds is None:
            return {}
        plans = [tuple(first)]
        ids = get_episode(record.task_id, record.seed).object_ids()
        for row in record.rounds:
            steps = parse_plan(row.raw_output, ids).valid_steps() if row.parse is not None else []
            plans.append(tuple(steps[: len(row.plan or ())]))
        config = self.config
        state = StateView(VIEWS, config.resolution, config.labels)
        rounds = tuple(plans[:round_index])
        job = ExecutionJob(record.task_id, record.seed, config.executor_config(), rounds, state)
        shown = execute_job(job).state
        return dict(shown.images) if shown is not None else {}

    def close(self) -> None:
        """Release the renderer, if one was made."""
        if self._source is not None:
            self._source.close()
            self._source = None


def run_views(render: bool) -> Callable[[Path, RunManifest], RunViews]:
    """The view source of each run of a gallery (``render``: render what no file keeps)."""
    return partial(RunViews, render=render)
