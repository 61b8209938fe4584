"""Where a GT execution's wall time goes, and two source trees compared on the same executions.

Usage: ``python benchmarks/execution_parts.py [--episodes task:seed,...] [--against PATH
[--clock cpu]]``

Executes the GT plans of ``--episodes`` (default: four typical episodes and four planning-heavy
long-horizon ones) back to back in one process and prints the wall time by part: physics steps
(``mj_step``, the Python UAV controller, contact bookkeeping, the rest of the loop), IK solves
(with their QP iterations), collision checks (computed and answered from the cache), and the
rest (planning in Python, scene build, goal check). The timers add about 0.3 µs per call.

With ``--against PATH`` (another checkout of vlm-bench, e.g. ``git worktree add /tmp/old REV``)
each episode is executed once by this tree and once by that one, alternately, each in a fresh
process without timers, and the script prints each episode's wall time (``--clock cpu``: its
CPU time, steadier on a loaded machine) in both, the ratio, and
whether the two results are equal (every field of the execution result but its wall time): a
change meant to keep outcomes shows ``equal`` everywhere.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from collections import Counter, defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine

DEFAULT = (
    "standard_pick_place:0,variant_green_nut:1,place_on_flat_surface:2,cross_color_sorting:5,"
    "category_sorting:1,tower_stacking:1,multi_object_sorting:3,stacking_nesting:5"
)
REPO = Path(__file__).resolve().parent.parent


def _episodes(text: str) -> list[tuple[str, int]]:
    return [(e.rsplit(":", 1)[0], int(e.rsplit(":", 1)[1])) for e in text.split(",") if e]


def _execute(task: str, seed: int) -> tuple[float, float, dict[str, Any], float]:
    """Wall time, simulated time, the result (without its wall time) and the CPU time of one
    GT execution."""
    from vlm_bench.episodes import make_episode
    from vlm_bench.executor import execute_plan

    episode = make_episode(task, seed)
    t0, c0 = time.perf_counter(), time.thread_time()
    result = execute_plan(episode, episode.gt_plan)
    wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
    dump = json.loads(result.model_dump_json(exclude={"wall_time_s"}))
    return wall, result.sim_time_s, dump, cpu


class _Timers:
    """Wraps functions with wall-time and call counters."""

    def __init__(self) -> None:
        self.seconds: defaultdict[str, float] = defaultdict(float)
        self.calls: Counter[str] = Counter()

    def wrap(self, owner: Any, name: str, label: str) -> None:
        inner: Callable[..., Any] = getattr(owner, name)
        seconds, calls, clock = self.seconds, self.calls, time.perf_counter

        def timed(*args: Any, **kwargs: Any) -> Any:
            t0 = clock()
            try:
                return inner(*args, **kwargs)
            finally:
                seconds[label] += clock() - t0
                calls[label] += 1

        setattr(owner, name, timed)


def parts(episodes: list[tuple[str, int]]) -> None:
    """Execute ``episodes`` with timers and print the table of parts."""
    import mujoco

    from vlm_bench.executor import sim_loop
    from vlm_bench.executor.motion import collision_check, ik, ik_qp
    from vlm_bench.sim import uav_control

    timers = _Timers()
    timers.wrap(sim_loop.SimLoop, "control_step", "physics")
    timers.wrap(uav_control.UavController, "apply", "uav")
    timers.wrap(sim_loop.SimLoop, "_record_contacts", "contacts")
    timers.wrap(mujoco, "mj_step", "mj_step")  # the process ends with the table: not undone
    timers.wrap(ik.ArmIk, "_solve", "ik")
    timers.wrap(ik_qp.IkQp, "velocity", "ik_iterations")
    timers.wrap(collision_check.CollisionChecker, "collisions", "checks")
    timers.wrap(collision_check.CollisionChecker, "_collide", "computed")
    wall = sim = 0.0
    for task, seed in episodes:
        w, s, _, _ = _execute(task, seed)
        wall, sim = wall + w, sim + s
        print(f"{task} seed {seed}: {s:.1f} s simulated in {w:.2f} s ({s / w:.1f}x)")
    t, n = timers.seconds, timers.calls
    physics_rest = t["physics"] - t["mj_step"] - t["uav"] - t["contacts"]
    rows = [
        ("physics steps", t["physics"], n["mj_step"], "steps"),
        ("· mj_step", t["mj_step"], n["mj_step"], "steps"),
        ("· UAV controller (Python)", t["uav"], n["uav"], "steps"),
        ("· contact bookkeeping", t["contacts"], n["contacts"], "steps"),
        ("· rest of the loop", physics_rest, n["physics"], "control steps"),
        ("IK solves", t["ik"], n["ik"], "solves"),
        ("· QP iterations", t["ik_iterations"], n["ik_iterations"], "iterations"),
        ("collision checks", t["checks"], n["checks"], "checks"),
        ("· computed (not cached)", t["computed"], n["computed"], "checks"),
        ("rest (planning, build, goals)", wall - t["physics"] - t["ik"] - t["checks"], 0, ""),
    ]
    print(f"\nmachine: {machine()}")
    print(
        f"{len(episodes)} executions: {sim:.1f} s simulated in {wall:.2f} s ({sim / wall:.1f}x)\n"
    )
    print("| part | s | share | calls | µs/call |")
    print("|---|---|---|---|---|")
    for label, seconds, calls, unit in rows:
        per = f"{seconds / calls * 1e6:.1f}" if calls else ""
        count = f"{calls:,} {unit}" if calls else ""
        print(f"| {label} | {seconds:.2f} | {seconds / wall:.0%} | {count} | {per} |")


def compare(episodes: list[tuple[str, int]], other: Path, clock: str) -> None:
    """Execute each episode in this tree and in ``other``, alternately, and compare their
    ``clock`` (wall or cpu) seconds."""
    trees = {"this": REPO, "other": other.resolve()}
    print(f"machine: {machine()}\nthis: {REPO}\nother: {trees['other']}\n")
    print(f"{clock} seconds of each execution\n")
    print("| episode | this s | other s | other / this | results |")
    print("|---|---|---|---|---|")
    total = {"this": 0.0, "other": 0.0}
    equal = 0
    for task, seed in episodes:
        out: dict[str, dict[str, Any]] = {}
        for name, tree in trees.items():
            env = {**os.environ, "PYTHONPATH": str(tree)}
            run = subprocess.run(
                [sys.executable, __file__, "--worker", f"{task}:{seed}"],
                env=env,
                capture_output=True,
                text=True,
                check=True,
                cwd=tree,
            )
            out[name] = json.loads(run.stdout.strip().splitlines()[-1])
            if not Path(out[name]["code"]).is_relative_to(tree):  # the tree's code, not another
                raise SystemExit(f"{name} ran {out[name]['code']}, not code under {tree}")
            total[name] += out[name][clock]
        same = out["this"]["result"] == out["other"]["result"]
        equal += same
        a, b = out["this"][clock], out["other"][clock]
        print(
            f"| {task}:{seed} | {a:.2f} | {b:.2f} | {b / a:.2f} | {'equal' if same else 'DIFFER'} |"
        )
    a, b = total["this"], total["other"]
    print(f"| **all** | {a:.2f} | {b:.2f} | **{b / a:.2f}** | {equal}/{len(episodes)} equal |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", default=DEFAULT, help="task:seed list, comma-separated")
    parser.add_argument("--against", type=Path, default=None, help="another vlm-bench checkout")
    parser.add_argument(
        "--clock",
        choices=("wall", "cpu"),
        default="wall",
        help="with --against: compare wall or CPU seconds (cpu: a loaded machine)",
    )
    parser.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker is not None:  # one execution, in the tree on PYTHONPATH: a JSON line
        ((task, seed),) = _episodes(args.worker)
        import vlm_bench

        wall, sim, result, cpu = _execute(task, seed)
        code = vlm_bench.__file__
        print(json.dumps({"wall": wall, "cpu": cpu, "sim": sim, "result": result, "code": code}))
    elif args.against is not None:
        compare(_episodes(args.episodes), args.against, args.clock)
    else:
        parts(_episodes(args.episodes))


if __name__ == "__main__":
    main()
