"""Execute every GT plan in the simulator: success rate, real-time factor per suite, sweep time.

Usage: ``python benchmarks/oracle_sweep.py [--seeds 0-9] [--workers 2] [--out sweep.jsonl]``

Each episode runs in a worker process (scene build + execution + goal check). The real-time
factor is simulated seconds per wall second of the execution itself, summed over a suite's
episodes; the sweep time is the wall time of the whole pool. Failures are listed with reasons.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine
from _pool import pooled_rows


def _one(job: tuple[str, int]) -> dict[str, object]:
    from vlm_bench.episodes import get_episode
    from vlm_bench.executor import execute_plan

    task, seed = job
    episode = get_episode(task, seed)  # the committed GT for seeds 0-9
    result = execute_plan(episode, episode.gt_plan)
    return {
        "task": task,
        "seed": seed,
        "suite": episode.suite.value,
        "success": result.exec_success,
        "reason": result.failure_reason,
        "sim_s": result.sim_time_s,
        "wall_s": result.wall_time_s,
        "total": result.scores.total if result.scores else None,
    }


def _seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0", help="seed range, e.g. 0-9")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--tasks", default="", help="comma-separated task ids (default: all)")
    parser.add_argument("--out", type=Path, default=None, help="write one JSON line per episode")
    parser.add_argument(
        "--episodes",
        type=Path,
        default=None,
        help="a JSON list of 'task:seed' to execute instead of --tasks x --seeds",
    )
    args = parser.parse_args()

    from vlm_bench.catalog.tasks import all_tasks

    tasks = args.tasks.split(",") if args.tasks else [t.id for t in all_tasks()]
    jobs = [(t, s) for s in _seeds(args.seeds) for t in tasks]
    if args.episodes is not None:
        keys = json.loads(args.episodes.read_text())
        jobs = [(k.rsplit(":", 1)[0], int(k.rsplit(":", 1)[1])) for k in keys]
    t0 = time.perf_counter()
    rows = pooled_rows(_one, jobs, args.workers, args.out)
    sweep = time.perf_counter() - t0

    by_suite: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for row in rows:
        by_suite[str(row["suite"])].append(row)
    print(f"machine: {machine()}")
    print(
        f"{len(rows)} episodes (seeds {args.seeds}), {args.workers} workers, "
        f"sweep wall time {sweep:.0f} s\n"
    )
    print("| suite | episodes | success | sim s/episode | real-time factor |")
    print("|---|---|---|---|---|")
    for suite, group in sorted(by_suite.items()):
        sim = sum(float(r["sim_s"]) for r in group)
        wall = sum(float(r["wall_s"]) for r in group)
        ok = sum(bool(r["success"]) for r in group)
        print(
            f"| {suite} | {len(group)} | {ok}/{len(group)} | {sim / len(group):.1f} | "
            f"{sim / wall:.1f}x |"
        )
    failures = sorted(
        (str(r["task"]), int(r["seed"]), str(r["reason"])) for r in rows if not r["success"]
    )
    if failures:
        print(f"\nfailures ({len(failures)}):")
        for task, seed, reason in failures:
            print(f"  {task} seed {seed}: {reason}")


if __name__ == "__main__":
    main()
