"""What the planner's path checks miss between their samples.

Usage: ``python benchmarks/path_audit.py [--seeds 3] [--tasks a,b] [--workers 2] [--dense 8]
[--out audit.jsonl]``

Executes the committed GT plans (default: every task, seed 3). Every path the executor checks
posture by posture (``ArmCore.hits_at``: a reach's way in and way down, a line's control
steps, a place's descent) and finds clear (a check with a negative contact limit, whose caller
has rejected the plan already, is not one) is checked again at ``--dense`` postures per
interval (joint-space blends between consecutive samples). The table counts the clear paths,
those whose denser check touches something, and the deepest such contact (mm, from MuJoCo's
signed distance of the robot's or held object's contact): what the sampling lets through.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections import Counter
from itertools import pairwise
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine
from _pool import pooled_rows


def touched_between(
    core: Any, postures: list[Any], query: Any, dense: int
) -> tuple[set[str], float]:
    """What ``query``'s checks would find between consecutive ``postures`` (``dense`` - 1
    joint-space blends per interval, the ends left out): the bodies touched and the deepest
    penetration (m) of a contact of the robot or the held object with one of them."""
    model, data, checker = core.loop.model, core.loop.data, core.checker
    check = checker._checker(query.clearance, query.carried)
    scratch, own = check.data, check.own
    touched: set[str] = set()
    depth = 0.0
    for a, b in pairwise(postures):
        for k in range(1, dense):
            hits = set(checker._collide(data, a + (b - a) * k / dense, query))
            if not hits:
                continue
            touched.update(model.body(model.geom_bodyid[g]).name for g in hits)
            for (g0, g1), dist in zip(
                scratch.contact.geom.tolist(), scratch.contact.dist.tolist(), strict=True
            ):
                if (g0 in hits and own[g1]) or (g1 in hits and own[g0]):
                    depth = max(depth, -dist)
    return touched, depth


def _one(job: tuple[str, int, int]) -> dict[str, Any]:
    from vlm_bench.episodes import get_episode
    from vlm_bench.executor import execute_plan
    from vlm_bench.executor.motion.arm_core import ArmCore

    task, seed, dense = job
    clear, missed = 0, []
    inner = ArmCore.hits_at

    def audited(self: ArmCore, postures: Any, query: Any, limit: float = float("inf")) -> int:
        nonlocal clear
        postures = list(postures)
        total = inner(self, postures, query, limit)
        if total or limit < 0 or len(postures) < 2:
            return total  # touching, or not checked (a caller over its limit already)
        clear += 1
        touched, depth = touched_between(self, postures, query, dense)
        if touched:
            missed.append({"bodies": sorted(touched), "depth_mm": round(depth * 1000, 2)})
        return total

    ArmCore.hits_at = audited  # type: ignore[method-assign]
    try:
        episode = get_episode(task, seed)
        result = execute_plan(episode, episode.gt_plan)
    finally:
        ArmCore.hits_at = inner  # type: ignore[method-assign]
    return {
        "task": task,
        "seed": seed,
        "success": result.exec_success,
        "clear": clear,
        "missed": missed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="3", help="seed range, e.g. 0-9")
    parser.add_argument("--tasks", default="", help="comma-separated task ids (default: all)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--dense", type=int, default=8, help="checks per sampled interval")
    parser.add_argument("--out", type=Path, default=None, help="write one JSON line per episode")
    args = parser.parse_args()

    from vlm_bench.catalog.tasks import all_tasks
    from vlm_bench.cli.options import parse_seeds

    tasks = args.tasks.split(",") if args.tasks else [t.id for t in all_tasks()]
    jobs = [(t, s, args.dense) for s in parse_seeds(args.seeds) for t in tasks]
    rows = pooled_rows(_one, jobs, args.workers, args.out)
    misses = [(r["task"], r["seed"], m) for r in rows for m in r["missed"]]
    clear = sum(int(r["clear"]) for r in rows)
    ok = sum(bool(r["success"]) for r in rows)
    print(f"machine: {machine()}")
    print(f"{len(rows)} executions (seeds {args.seeds}), {ok} succeed; {args.dense}x denser\n")
    print("| clear paths | touching between samples | deepest contact (mm) |")
    print("|---|---|---|")
    deepest = max((float(m["depth_mm"]) for _, _, m in misses), default=0.0)
    print(f"| {clear} | {len(misses)} ({100 * len(misses) / max(clear, 1):.2f} %) | {deepest} |")
    if misses:
        print("\nby body touched:")
        for body, n in Counter(b for _, _, m in misses for b in m["bodies"]).most_common():
            print(f"  {body}: {n}")
        print("\nmisses:")
        for task, seed, m in sorted(misses, key=lambda x: -float(x[2]["depth_mm"])):
            print(f"  {task} seed {seed}: {', '.join(m['bodies'])}, {m['depth_mm']} mm")


if __name__ == "__main__":
    main()
