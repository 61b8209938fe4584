"""``vlm-bench export sft``: planner SFT data from train seeds, streamed into a Hugging Face
dataset folder (docs/training.md#sft-export).

Episodes come in benchmark order (task, seed, instruction variant), each drawn once for both
variants and rendered once; a train episode that repeats a test episode
(:func:`~vlm_bench.episodes.train_split.repeat_of`) is left out and counted. With
``perturb`` every episode is also executed from its GT plan under the perturbations and
``rules`` replans after each failed round (:mod:`~vlm_bench.training.recovery`); the replans
of an episode that recovered become replan examples.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from itertools import groupby

from vlm_bench.episodes.train_split import test_seeds_in, train_episodes
from vlm_bench.errors import ConfigError
from vlm_bench.runner.episode_request import run_snapshots
from vlm_bench.runner.selection import EpisodeRef, select_episodes
from vlm_bench.training.recovery import recover
from vlm_bench.training.sft_rows import SftExample, episode_examples
from vlm_bench.types.run import RunConfig


@dataclass
class SftCounts:
    """What an export wrote and left out."""

    rows: Counter[str] = field(default_factory=Counter)
    """Rows by kind (plan, replan)."""
    episodes: int = 0
    """Task × seed scenes used."""
    repeats: list[str] = field(default_factory=list)
    """task/seed of train episodes left out as repeats of a test episode."""
    ends: Counter[str] = field(default_factory=Counter)
    """Perturbed executions by how they ended: success (round 0), recovered, or the loop's end
    (max_rounds, budget, no_plan, executor_crash)."""


def check_seeds(config: RunConfig, allow_test_seeds: bool) -> None:
    """Refuse test seeds in a training export unless allowed.

    Raises:
        ConfigError: Names the test seeds asked for and the option that allows them.
    """
    found = test_seeds_in(config.seeds)
    if found and not allow_test_seeds:
        shown = ", ".join(map(str, found[:5])) + (", ..." if len(found) > 5 else "")
        raise ConfigError(
            f"test seeds asked for ({shown}): seeds 0-9 are the benchmark's GT and training on "
            "them leaks the test set; use train seeds (10 and up) or --allow-test-seeds"
        )


def sft_examples(
    config: RunConfig, counts: SftCounts, *, allow_test_seeds: bool = False
) -> Iterator[tuple[int, list[SftExample]]]:
    """Per task × seed of ``config``'s selection, in order: ``1`` scene done and its rows of
    every instruction variant (none for a repeat of a test episode). ``config.perturb`` set:
    replan rows from the recovery of each perturbed execution.

    The seeds and the selection are checked at the call, before any row is drawn.

    Raises:
        ConfigError: Test seeds without ``allow_test_seeds``. UnknownNameError: A task id.
    """
    check_seeds(config, allow_test_seeds)
    refs = select_episodes(config)
    return _rows(config, refs, counts, allow_test_seeds)


def _rows(
    config: RunConfig, refs: list[EpisodeRef], counts: SftCounts, allow_test_seeds: bool
) -> Iterator[tuple[int, list[SftExample]]]:
    source = run_snapshots(config, None)
    try:
        for (task_id, seed), group in groupby(refs, key=lambda r: (r.task_id, r.seed)):
            variants: list[EpisodeRef] = list(group)
            (split,) = train_episodes(task_id, [seed], allow_test_seeds=allow_test_seeds)
            if split.repeats is not None:
                counts.repeats.append(f"{task_id}/{seed}")
                yield 1, []
                continue
            episode = split.episode
            counts.episodes += 1
            images = source.images(episode) if config.images else None
            recovery = None
            if config.perturb is not None or config.uav_noise > 0:
                recovery = recover(episode, config)
                counts.ends["recovered" if recovery.recovered else recovery.end] += 1
            rows = [
                row
                for ref in variants
                for row in episode_examples(config, ref, episode, images, recovery)
            ]
            counts.rows.update(row.kind for row in rows)
            yield 1, rows
    finally:
        source.close()


def scene_count(config: RunConfig) -> int:
    """Task × seed scenes an export of ``config`` visits (the progress bar's total)."""
    return len({(r.task_id, r.seed) for r in select_episodes(config)})


def row_bound(config: RunConfig) -> int:
    """The most rows an export of ``config`` can write (a plan row per episode, and with
    perturbations a replan row per replan)."""
    rounds = 1 + (config.max_rounds if config.loop == "closed" else 0)
    return len(select_episodes(config)) * rounds
