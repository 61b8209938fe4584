"""Grasps under a sub-millimetre nudge: the GT plans that pick objects of given kinds, executed
again with each picked object's start moved by a fraction of a millimetre.

Usage: ``python benchmarks/grasp_jitter.py [--kinds tomato_can,meat_can,cleanser,lidar]
[--offsets 0.3,0.7,1.5] [--seeds 0-9] [--workers 2] [--out jitter.jsonl]``

Two CPUs execute the same code differently in the last bits, and a grasp that is fragile (a
contact near the edge of a finger pad, a generic convex collision whose normal can flip) fails
on one machine and not on another: that is how a cup's cylinder collider was found
(docs/decisions.md). A nudge of 0.3-1.5 mm stands in for those last bits. For every committed
episode (seeds 0-9) whose GT plan picks an object of the given kinds, each offset moves every
such object along the world x axis by that many millimetres, the GT plan is executed, and the
result is recorded with the highest angular speed (rad/s) any of those objects reaches while
held (a spinning object in the fingers is the symptom of a flipped contact normal). Prints the
failures with their reasons, and the angular speeds' maximum per kind.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine
from _pool import pooled_rows

DEFAULT_KINDS = "tomato_can,meat_can,cleanser,lidar"


def _picked(episode: object, kinds: set[str]) -> list[str]:
    """Ids of the objects of ``kinds`` the GT plan picks, in plan order."""
    from vlm_bench.types.plan import ArmStep

    kind_of = {o.id: o.kind for o in episode.objects}  # type: ignore[attr-defined]
    ids: list[str] = []
    for step in episode.gt_plan:  # type: ignore[attr-defined]
        if not isinstance(step, ArmStep) or step.skill != "pick":
            continue
        if kind_of.get(step.object) in kinds and step.object not in ids:
            ids.append(step.object)
    return ids


def _one(job: tuple[str, int, float, tuple[str, ...]]) -> dict[str, object]:
    import mujoco

    from vlm_bench.episodes import get_episode
    from vlm_bench.executor import execute_plan

    task, seed, offset_mm, ids = job
    episode = get_episode(task, seed)
    dx = offset_mm / 1000.0
    objects = tuple(
        o.model_copy(update={"pos": (o.pos[0] + dx, o.pos[1], o.pos[2])}) if o.id in ids else o
        for o in episode.objects
    )
    nudged = episode.model_copy(update={"objects": objects})
    spin = dict.fromkeys(ids, 0.0)
    dofs: dict[str, int] = {}

    def watch(loop: object) -> None:
        model, data = loop.model, loop.data  # type: ignore[attr-defined]
        if not dofs:
            for i in ids:
                joint = model.body(i).jntadr[0]
                dofs[i] = int(model.jnt_dofadr[joint])
        name = loop.held  # type: ignore[attr-defined]
        if name in spin:
            w = data.qvel[dofs[name] + 3 : dofs[name] + 6]
            spin[name] = max(spin[name], float(mujoco.mju_norm3(w)))

    start = time.perf_counter()
    result = execute_plan(nudged, nudged.gt_plan, observers=[watch])
    return {
        "task": task,
        "seed": seed,
        "offset_mm": offset_mm,
        "objects": list(ids),
        "kinds": [next(o.kind for o in episode.objects if o.id == i) for i in ids],
        "success": result.exec_success,
        "reason": result.failure_reason,
        "max_spin": spin,
        "wall_s": time.perf_counter() - start,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kinds", default=DEFAULT_KINDS, help="comma-separated object kinds")
    parser.add_argument("--offsets", default="0.3,0.7,1.5", help="nudges along x (mm)")
    parser.add_argument("--seeds", default="0-9", help="seed range, e.g. 0-9")
    parser.add_argument("--tasks", default="", help="comma-separated task ids (default: all)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=None, help="write one JSON line per run")
    args = parser.parse_args()

    from vlm_bench.catalog.tasks import all_tasks
    from vlm_bench.cli.options import parse_seeds
    from vlm_bench.episodes import get_episode

    kinds = set(args.kinds.split(","))
    offsets = [float(x) for x in args.offsets.split(",")]
    tasks = args.tasks.split(",") if args.tasks else [t.id for t in all_tasks()]
    jobs: list[tuple[str, int, float, tuple[str, ...]]] = []
    for task in tasks:
        for seed in parse_seeds(args.seeds):
            ids = tuple(_picked(get_episode(task, seed), kinds))
            if ids:
                jobs.extend((task, seed, off, ids) for off in offsets)
    print(f"machine: {machine()}")
    print(f"{len(jobs) // len(offsets)} episodes pick {sorted(kinds)}; {len(jobs)} executions")
    t0 = time.perf_counter()
    rows = pooled_rows(_one, jobs, args.workers, args.out)
    failed = [r for r in rows if not r["success"]]
    wall = time.perf_counter() - t0
    print(f"wall time {wall:.0f} s; {len(rows) - len(failed)}/{len(rows)} succeed")
    spins: dict[str, list[float]] = defaultdict(list)
    for r in rows:
        for i, kind in zip(r["objects"], r["kinds"], strict=True):
            spins[kind].append(r["max_spin"][i])
    print("| kind | executions | highest spin while held (rad/s) | over 5 rad/s |")
    print("|---|---|---|---|")
    for kind, values in sorted(spins.items()):
        over = sum(v > 5.0 for v in values)
        print(f"| {kind} | {len(values)} | {max(values):.2f} | {over} |")
    for r in sorted(failed, key=lambda r: (r["task"], r["seed"], r["offset_mm"])):
        print(f"  FAILED {r['task']} seed {r['seed']} +{r['offset_mm']} mm: {r['reason']}")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
