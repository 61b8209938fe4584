"""``vlm-bench export demos``: scripted executions of GT plans as a LeRobot dataset
(docs/demos.md).

For every selected task × train seed, the scripted executor executes the episode's GT plan
with a seeded :class:`~vlm_bench.vla.demos.variation.DemoVariation` while a
:class:`~vlm_bench.vla.demos.recorder.DemoRecorder` records the cameras, the state and the
gym environment's 12-D action every 50 ms (:data:`FPS` = 20 Hz, the control rate, so a
replay of the actions in the gym environment issues the same commands). Successful
executions become LeRobot episodes (one per execution, or one per ARM step with
``per_arm_step``), the task text being the instruction (or the ARM step's command);
failures are counted, not written.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from vlm_bench.catalog.gt_episodes import MATERIALISED_SEEDS
from vlm_bench.catalog.tasks import get_task, tasks_in
from vlm_bench.episodes.train_split import train_episodes
from vlm_bench.errors import ConfigError
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep
from vlm_bench.vla.demos.card import demos_card
from vlm_bench.vla.demos.config import (
    FPS,
    SOURCE_SEED,
    SOURCE_STEP,
    SOURCE_TASK,
    DemoExportConfig,
    DemoExportSummary,
)
from vlm_bench.vla.demos.lerobot_writer import EpisodeData, LeRobotWriter, require_writer_packages
from vlm_bench.vla.demos.record import Demonstration, record_demo
from vlm_bench.vla.demos.variation import draw_variation
from vlm_bench.vla.observation import ObservationConfig

REPEAT = "repeats_a_test_episode"
"""Why a train seed is left out when its episode repeats a test episode
(:func:`~vlm_bench.episodes.train_split.repeat_of`)."""


def demo_source(demo: Demonstration) -> dict[str, Any]:
    """The episodes-table columns of a demonstration: its episode and drawn variation."""
    draw = demo.draw
    return {
        SOURCE_TASK: demo.episode.task_id,
        SOURCE_SEED: demo.episode.seed,
        "vlm_bench/speed": draw.speed,
        "vlm_bench/accel": draw.accel,
        "vlm_bench/stow_s": draw.stow_s,
    }


def selected_task_ids(config: DemoExportConfig) -> list[str]:
    """The export's task ids in benchmark order (validates every id)."""
    if config.tasks:
        wanted = {get_task(t).id for t in config.tasks}
        return [t.id for t in tasks_in(None) if t.id in wanted]
    return [t.id for t in tasks_in(config.suite)]


def check_request(config: DemoExportConfig, out: Path, force: bool) -> None:
    """Refuse test seeds (unless allowed), an odd image size and a non-empty folder.

    Raises:
        ConfigError: The first problem, in one line.
    """
    tests = sorted(s for s in set(config.seeds) if s in MATERIALISED_SEEDS)
    if tests and not config.allow_test_seeds:
        raise ConfigError(
            f"test seeds asked for ({', '.join(map(str, tests[:5]))}): seeds 0-9 are the "
            "benchmark's test set and training on them leaks it; use train seeds (10 and up) "
            "or --allow-test-seeds"
        )
    if config.size % 2:
        raise ConfigError(f"--size must be even (H.264 with yuv420p), got {config.size}")
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out} is a file, not a folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise ConfigError(f"{out} is not empty; choose an empty folder or add --force")


def _episodes_of(demo: Demonstration, config: DemoExportConfig) -> list[EpisodeData]:
    """The LeRobot episodes of a kept demonstration."""
    frames = demo.frames
    states = np.stack(frames.states)
    actions = np.stack(frames.actions)
    images = {v: np.stack(frames.images[v]) for v in frames.views}
    source = demo_source(demo)
    if not config.per_arm_step:
        task = demo.episode.instruction(config.variant)
        return [EpisodeData(task, states, actions, images, {**source, SOURCE_STEP: -1})]
    marks = np.array(frames.arm_steps)
    out = []
    for index in sorted(set(frames.arm_steps) - {-1}):
        rows = np.flatnonzero(marks == index)
        step = demo.episode.gt_plan[index]
        if not isinstance(step, ArmStep):
            continue
        text = f"{step.skill} {step.object}" + (f" to {step.target}" if step.target else "")
        sel = slice(int(rows[0]), int(rows[-1]) + 1)
        cut = {k: v[sel] for k, v in images.items()}
        source = {**demo_source(demo), SOURCE_STEP: index}
        out.append(EpisodeData(text, states[sel], actions[sel], cut, source))
    return out


def export_demos(
    config: DemoExportConfig,
    out: Path,
    *,
    force: bool = False,
    on_progress: Callable[[Demonstration], None] | None = None,
) -> DemoExportSummary:
    """Record and write the demonstrations of ``config`` into ``out`` (module doc).

    Args:
        config: Tasks, seeds, cameras, variation.
        out: Dataset folder (must be empty unless ``force``).
        force: Write into a non-empty folder (its dataset files are replaced).
        on_progress: Called after every execution.

    Raises:
        ConfigError: Test seeds, a non-empty folder, a bad size.
        MissingExtraError: pyarrow or imageio-ffmpeg missing (the ``demos`` extra).
    """
    check_request(config, out, force)
    require_writer_packages()
    task_ids = selected_task_ids(config)
    observation = ObservationConfig(views=config.views, size=config.size)
    for part in ("data", "videos", "meta"):  # a forced export replaces an earlier one
        shutil.rmtree(out / part, ignore_errors=True)
    out.mkdir(parents=True, exist_ok=True)
    writer = LeRobotWriter(out, config.views, config.size, FPS)
    summary = DemoExportSummary(folder=out)
    renderer = SnapshotRenderer()
    try:
        for task_id in task_ids:
            for split in train_episodes(task_id, config.seeds, allow_test_seeds=True):
                if split.repeats is not None:  # a train seed whose scene is a test episode's
                    summary.failures[REPEAT] += 1
                    continue
                demo = _record(split.episode, config, observation, renderer)
                summary.executions += 1
                if demo.kept:
                    summary.kept += 1
                    for episode in _episodes_of(demo, config):
                        writer.add(episode)
                        summary.episodes += 1
                        summary.frames += len(episode)
                else:
                    summary.failures[_failure(demo)] += 1
                if on_progress is not None:
                    on_progress(demo)
    finally:
        renderer.close()
        writer.close()
    (out / "README.md").write_text(demos_card(config, summary, task_ids))
    return summary


def _record(
    episode: Episode,
    config: DemoExportConfig,
    observation: ObservationConfig,
    renderer: SnapshotRenderer,
) -> Demonstration:
    draw = draw_variation(config.variation, episode.task_id, episode.seed)
    return record_demo(episode, draw, observation, renderer)


def _failure(demo: Demonstration) -> str:
    if demo.result.exec_success:
        return "action_out_of_bounds"
    code = demo.result.failure_code
    return str(code) if code is not None else "failed"


def count_executions(config: DemoExportConfig) -> int:
    """Executions an export of ``config`` makes (the progress bar's total)."""
    return len(selected_task_ids(config)) * len(config.seeds)
