"""Legibility of the third-person views: heading-arrow length and task-object sizes in pixels.

Usage: ``python benchmarks/view_legibility.py [--seeds 0-9] [--tasks a,b] [--workers 1]
[--size 448] [--out rows.jsonl]``

Builds each episode's scene at its start state, renders segmentation images of the ``overhead``
and ``side`` views (as rendered, and with the robot hidden) and measures, with
:func:`vlm_bench.sim.footprint.measure_legibility`, the seen length of the UAV's heading arrow
and, for every task object (:func:`vlm_bench.sim.cameras.task_objects`: the objects the GT
plan's ARM steps name, the owners of the parts they name, every movable non-support object),
the shorter side of its pixel bounding box. Episodes are judged by
:func:`vlm_bench.sim.footprint.legibility_failures` (the criterion is in that module's
docstring). It also counts, with :mod:`vlm_bench.sim.view_checks`, the supports under task
objects that show their top in a view, those that show their top and full height down to the
floor, and the label tags that cover a task object's pixels; it exits 1 when an episode fails
the criterion, a support's top or full height is shown in no view, or a tag covers a task
object. Episodes are the
materialised GT's. Prints the minima per view, the smallest objects by kind, the worst ten
episodes and the wall time; ``--out`` writes one JSON line per episode as it finishes.
"""

from __future__ import annotations

import argparse
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

_RENDERER: Any = None
VIEWS = ("overhead", "side")


def _one(job: tuple[str, int, int]) -> dict[str, Any]:
    global _RENDERER
    from vlm_bench.catalog.world_catalog import object_kind
    from vlm_bench.episodes import get_episode
    from vlm_bench.sim.footprint import measure_scene_legibility
    from vlm_bench.sim.render import SnapshotRenderer
    from vlm_bench.sim.scene import build_scene
    from vlm_bench.sim.view_checks import (
        label_overlaps,
        support_heights,
        support_tops,
        view_segmentations,
    )

    if _RENDERER is None:
        _RENDERER = SnapshotRenderer(shadows=False)
    task, seed, size = job
    t0 = time.perf_counter()
    episode = get_episode(task, seed)
    scene = build_scene(episode)
    measured = measure_scene_legibility(scene, _RENDERER, size)
    row = measured.to_json()
    segs = view_segmentations(scene, _RENDERER, size)
    row["support_tops"] = support_tops(scene, _RENDERER, size, segs=segs)
    row["support_heights"] = support_heights(scene, _RENDERER, size, segs=segs)
    row["label_overlaps"] = label_overlaps(scene, _RENDERER, size, segs=segs)
    kinds = {o.id: o.kind for o in episode.objects}
    row["suite"] = episode.suite.value
    row["environment"] = episode.environment
    row["kinds"] = {name: kinds[name] for name in measured.objects}
    row["movable"] = {name: object_kind(kinds[name]).movable for name in measured.objects}
    row["seconds"] = round(time.perf_counter() - t0, 3)
    return row


def _seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def _object_min(row: dict[str, Any], view: str | None, key: str = "seen") -> int:
    """Smallest object footprint of an episode in ``view`` (None: best of the views)."""
    sizes = []
    for prints in row["objects"].values():
        if view is None:
            sizes.append(max(p[key] for p in prints.values()))
        else:
            sizes.append(prints[view][key])
    return min(sizes) if sizes else 10**6


def summarise(rows: list[dict[str, Any]], wall: float, workers: int) -> None:
    """Print the summary of measured episodes."""
    print(f"machine: {machine()}")
    print(
        f"episodes: {len(rows)}, workers: {workers}, wall time: {wall:.1f} s "
        f"({wall / max(len(rows), 1):.2f} s/episode)"
    )
    size = rows[0]["size"] if rows else 0
    print(f"image size: {size}")
    for view in VIEWS:
        worst = min(rows, key=lambda r: r["arrow"][view])
        print(
            f"min arrow {view:8}: {worst['arrow'][view]:6.1f} px "
            f"({worst['task']} seed {worst['seed']})"
        )
    for view in VIEWS:
        for key, what in (("seen", "as rendered"), ("clear", "robot hidden")):
            worst = min(rows, key=lambda r: _object_min(r, view, key))
            print(
                f"min object {view:8} {what:13}: {_object_min(worst, view, key):4d} px "
                f"({worst['task']} seed {worst['seed']})"
            )
    worst = min(rows, key=lambda r: _object_min(r, None))
    print(
        f"min object best of the two views: {_object_min(worst, None):4d} px "
        f"({worst['task']} seed {worst['seed']})"
    )
    by_kind: dict[str, list[int]] = defaultdict(lambda: [10**6, 10**6, 10**6])
    for row in rows:
        for name, prints in row["objects"].items():
            entry = by_kind[row["kinds"][name]]
            for k, view in enumerate(VIEWS):
                entry[k] = min(entry[k], prints[view]["seen"])
            entry[2] = min(entry[2], max(p["seen"] for p in prints.values()))
    print("min object px by kind (overhead, side, best of two):")
    for kind, (over, side, best) in sorted(by_kind.items(), key=lambda kv: kv[1][2]):
        print(f"  {kind:16} {over:4d} {side:4d} {best:4d}")
    tops = [any(views.values()) for r in rows for views in r["support_tops"].values()]
    hidden = [r for r in rows if not all(any(v.values()) for v in r["support_tops"].values())]
    print(
        f"height supports showing their top in a view: {sum(tops)} of {len(tops)}; "
        f"episodes with every top shown: {len(rows) - len(hidden)} of {len(rows)}"
    )
    for row in hidden[:10]:
        print(f"  {row['task']} seed {row['seed']}: {row['support_tops']}")
    heights = [any(views.values()) for r in rows for views in r["support_heights"].values()]
    short = [r for r in rows if not all(any(v.values()) for v in r["support_heights"].values())]
    print(
        f"height supports showing top and full height in a view: {sum(heights)} of "
        f"{len(heights)}; episodes with every one shown: {len(rows) - len(short)} of "
        f"{len(rows)}"
    )
    for view in VIEWS:
        count = sum(v[view] for r in rows for v in r["support_heights"].values())
        print(f"  shown in the {view} view: {count}")
    for row in short[:10]:
        print(f"  {row['task']} seed {row['seed']}: {row['support_heights']}")
    covered = [r for r in rows if r["label_overlaps"]]
    print(f"episodes where a label covers a task object: {len(covered)} of {len(rows)}")
    for row in covered[:10]:
        print(f"  {row['task']} seed {row['seed']}: {row['label_overlaps']}")
    failing = [r for r in rows if r["failures"]]
    print(f"episodes failing the criterion: {len(failing)} of {len(rows)}")
    print("worst 10 episodes (smallest task object, best of two views; failures):")
    for row in sorted(rows, key=lambda r: (_object_min(r, None), min(r["arrow"].values())))[:10]:
        arrows = " ".join(f"{v}={row['arrow'][v]:.0f}" for v in VIEWS)
        print(
            f"  {row['task']:32} seed {row['seed']}  object {_object_min(row, None):3d} px  "
            f"arrow {arrows}  {'; '.join(row['failures'][:4])}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-9", help="seed range, e.g. 0-9")
    parser.add_argument("--tasks", default="", help="comma-separated task ids (default: all)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--size", type=int, default=448, help="image side (px)")
    parser.add_argument("--out", type=Path, default=None, help="write one JSON line per episode")
    args = parser.parse_args()

    from vlm_bench.catalog.tasks import all_tasks

    tasks = args.tasks.split(",") if args.tasks else [t.id for t in all_tasks()]
    jobs = [(t, s, args.size) for s in _seeds(args.seeds) for t in tasks]
    t0 = time.perf_counter()
    rows = pooled_rows(_one, jobs, args.workers, args.out)
    summarise(rows, time.perf_counter() - t0, args.workers)
    unseen = any(
        not any(v.values())
        for r in rows
        for key in ("support_tops", "support_heights")
        for v in r[key].values()
    )
    sys.exit(1 if unseen or any(r["failures"] or r["label_overlaps"] for r in rows) else 0)


if __name__ == "__main__":
    main()
