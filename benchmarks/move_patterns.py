"""How much of a GT plan's UAV moves a planner could know from the task alone.

Usage: ``python benchmarks/move_patterns.py [--seeds 0-9] [--generate]``

Reads the materialised GT plans (``--generate``: builds the episodes instead) and prints:

* per task, its *vertical patterns*: the ``up``/``down`` moves of each segment (the moves before
  one ARM step) as one tuple per seed; the count of tasks with two or more distinct patterns,
  and of those whose later segments alone (after the first) show two or more (tables of
  different heights);
* how balanced the horizontal moves are per task: for the first horizontal move of a plan and
  for every later one, the share of seeds a leave-one-seed-out guess gets right (the most
  frequent direction the task's other seeds have at that segment; ties to the earlier
  direction) against the chance of an eight-way guess, and the largest share one direction
  takes at one (task, segment) over the seeds.
"""

from __future__ import annotations

import argparse
from collections import Counter, defaultdict

from vlm_bench.backends.blind_planner import Moves, segments
from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.types.plan import Direction


def _seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def plan_segments(seeds: list[int], generate: bool) -> dict[str, dict[int, list[Moves]]]:
    """task id -> seed -> the moves before each ARM step of the GT plan."""
    out: dict[str, dict[int, list[Moves]]] = {}
    for task in all_tasks():
        if generate:
            from vlm_bench.episodes import make_episode

            plans = {s: make_episode(task, s).gt_plan for s in seeds}
        else:
            eps = load_materialised(task).episodes
            plans = {e.seed: e.gt_plan for e in eps if e.seed in seeds}
        out[task.id] = {s: segments(p) for s, p in plans.items()}
    return out


def vertical_pattern(segs: list[Moves]) -> tuple[tuple[Direction, ...], ...]:
    """The vertical moves of each segment."""
    return tuple(tuple(d for d in m if not d.is_horizontal) for m in segs)


def _horizontal(moves: Moves) -> Direction | None:
    return next((d for d in moves if d.is_horizontal), None)


def _guess(directions: list[Direction]) -> Direction | None:
    counts = Counter(directions)
    order = list(Direction)
    return max(counts, key=lambda d: (counts[d], -order.index(d))) if counts else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-9")
    parser.add_argument("--generate", action="store_true", help="build episodes, not the files")
    args = parser.parse_args()
    table = plan_segments(_seeds(args.seeds), args.generate)

    varied = later = 0
    print("task: vertical patterns over seeds (count)")
    for task, by_seed in table.items():
        patterns = Counter(vertical_pattern(s) for s in by_seed.values())
        varied += len(patterns) >= 2
        later += len({vertical_pattern(s[1:]) for s in by_seed.values()}) >= 2
        shown = "; ".join(
            f"{'|'.join(','.join(d.value for d in seg) or '-' for seg in p)} x{n}"
            for p, n in patterns.most_common()
        )
        print(f"  {task}: {len(patterns)} pattern(s): {shown}")
    print(f"tasks with >= 2 vertical patterns: {varied} of {len(table)}")
    print(f"tasks with >= 2 vertical patterns after the first segment: {later} of {len(table)}")

    hits: dict[str, list[bool]] = defaultdict(list)
    top_share: dict[str, list[float]] = defaultdict(list)
    for by_seed in table.values():
        n_seg = max(len(s) for s in by_seed.values())
        first_seg = {
            seed: next((k for k, m in enumerate(segs) if _horizontal(m)), None)
            for seed, segs in by_seed.items()
        }
        for k in range(n_seg):
            moves = {seed: _horizontal(segs[k]) for seed, segs in by_seed.items() if k < len(segs)}
            for seed, move in moves.items():
                if move is None:
                    continue
                kind = "first" if first_seg[seed] == k else "later"
                others = [d for s, d in moves.items() if s != seed and d is not None]
                hits[kind].append(_guess(others) == move)
            present = [d for d in moves.values() if d is not None]
            if len(present) >= 5:
                kind = "first" if k == 0 else "later"
                top_share[kind].append(max(Counter(present).values()) / len(present))
    for kind in ("first", "later"):
        rate = 100 * sum(hits[kind]) / max(1, len(hits[kind]))
        shares = top_share[kind]
        print(
            f"{kind} horizontal moves: {len(hits[kind])}; leave-one-seed-out guess right "
            f"{rate:.1f} % (chance 12.5 %); most frequent direction per (task, segment): "
            f"mean {100 * sum(shares) / max(1, len(shares)):.0f} %, "
            f"max {100 * max(shares, default=0):.0f} %"
        )


if __name__ == "__main__":
    main()
