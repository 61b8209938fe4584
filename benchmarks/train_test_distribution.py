"""The train split against the test split: disjointness and distribution (docs/training.md#splits).

Usage: ``python benchmarks/train_test_distribution.py [--seeds 10-109] [--task ID ...]
[--workers 2]``

Draws the train episodes of every task (or ``--task``) with the generator, reads the committed
test episodes (seeds 0-9), and prints, as Markdown:

* disjointness: train episodes that repeat a test episode within the tolerance of
  :data:`vlm_bench.episodes.train_split.TOLERANCE`, and the closest any comes (the largest of
  its distances over their tolerances; 1 = at the tolerance);
* the share of each value in both splits, with the total-variation distance between them:
  table heights (the kind every ``table`` is built as), the vertical pattern of the first
  segment (``up``, ``down`` or none before the first ARM step) and of the later ones, the
  sector of the first horizontal move and of every horizontal move, and the UAV moves per plan.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter
from collections.abc import Iterable
from concurrent.futures import ProcessPoolExecutor

from vlm_bench.backends.blind_planner import Moves, segments
from vlm_bench.catalog.tasks import all_tasks, get_task
from vlm_bench.episodes.train_split import (
    TEST_SEEDS,
    TOLERANCE,
    nearest_test,
    test_episodes,
    train_episode,
)
from vlm_bench.types.episode import Episode

Features = dict[str, list[str]]


def features(episode: Episode) -> Features:
    """The values of one episode each distribution counts."""
    segs = segments(episode.gt_plan)
    first_h = next((d.value for m in segs for d in m if d.is_horizontal), "none")
    tables = [o.kind for o in episode.objects if o.kind.endswith("table")]
    return {
        "table height": tables,
        "first segment vertical": [_vertical(segs[0]) if segs else "none"],
        "later segments vertical": [_vertical(m) for m in segs[1:]],
        "first horizontal sector": [first_h],
        "every horizontal sector": [d.value for m in segs for d in m if d.is_horizontal],
        "UAV moves per plan": [str(len(episode.uav_steps()))],
    }


def _vertical(moves: Moves) -> str:
    return ",".join(d.value for d in moves if not d.is_horizontal) or "none"


def _train_one(job: tuple[str, int]) -> tuple[Features, float, int | None, str]:
    task_id, seed = job
    episode = train_episode(task_id, seed)
    test_seed, near = nearest_test(episode)
    ratio = near.ratio()
    repeat = test_seed if ratio <= 1.0 else None
    return features(episode), ratio, repeat, f"{task_id}/{seed}"


def _count(rows: Iterable[Features]) -> dict[str, Counter[str]]:
    out: dict[str, Counter[str]] = {}
    for row in rows:
        for name, values in row.items():
            out.setdefault(name, Counter()).update(values)
    return out


def _tv(a: Counter[str], b: Counter[str]) -> float:
    na, nb = sum(a.values()) or 1, sum(b.values()) or 1
    return 0.5 * sum(abs(a[k] / na - b[k] / nb) for k in set(a) | set(b))


def _seeds(text: str) -> list[int]:
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out.extend(range(int(lo), int(hi or lo) + 1))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="10-109", help="train seeds")
    parser.add_argument("--task", action="append", help="task id (repeatable; default all)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    tasks = [get_task(t).id for t in args.task] if args.task else [t.id for t in all_tasks()]
    seeds = _seeds(args.seeds)
    start = time.monotonic()
    test = _count(features(e) for t in tasks for e in test_episodes(t))
    jobs = [(t, s) for t in tasks for s in seeds]
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        results = list(pool.map(_train_one, jobs, chunksize=4))
    train = _count(r[0] for r in results)
    closest = min(results, key=lambda r: r[1])
    repeats = [(r[3], r[2]) for r in results if r[2] is not None]
    print(
        f"## Train seeds {args.seeds} against test seeds {TEST_SEEDS.start}-{TEST_SEEDS.stop - 1}"
    )
    print()
    print(f"{len(tasks)} tasks: {len(jobs)} train episodes, {len(tasks) * len(TEST_SEEDS)} test.")
    print(f"Repeat tolerance: {TOLERANCE}.")
    print(f"Train episodes repeating a test episode: {len(repeats)} {repeats[:10]}")
    print(f"Closest train episode to a test one: {closest[3]}, ratio {closest[1]:.2f}")
    print()
    print("| feature | value | test % | train % |")
    print("|---|---|---:|---:|")
    for name in test:
        a, b = test[name], train.get(name, Counter())
        na, nb = sum(a.values()) or 1, sum(b.values()) or 1
        for value in sorted(set(a) | set(b), key=lambda v: (-a[v] - b[v], v)):
            print(f"| {name} | {value} | {100 * a[value] / na:.1f} | {100 * b[value] / nb:.1f} |")
        print(f"| {name} | *total variation* | | {_tv(a, b):.3f} |")
    print()
    print(f"({time.monotonic() - start:.0f} s with {args.workers} workers, measured under load)")


if __name__ == "__main__":
    main()
