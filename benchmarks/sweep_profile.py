"""CPU of GT executions by phase, from worker processes, with cProfile's top functions.

Usage: ``python benchmarks/sweep_profile.py [--seeds 0-9] [--tasks a,b] [--episodes a:0,b:1]
[--workers 2] [--top 25] [--sort tottime] [--only PATH_PART] [--no-cprofile]``

Executes the committed GT plans like ``oracle_sweep.py`` (default: the whole sweep, 60 tasks x
seeds 0-9) in ``--workers`` processes. Each worker times its phases in CPU seconds (each call is
charged to the innermost phase it runs in) and runs cProfile over every execution; the parent
merges both and prints the phase table and the functions with the most own time.

Phases: start-up (the worker's imports), episode load, scene build (MJCF, compile, first
forward), physics (``mj_step``, the Python UAV controller, the rest of the loop: contact
bookkeeping and checks), IK solves, collision checks, rendering, and planning logic (everything
else in an execution: skills, motion planning in Python, goal check, scores). cProfile slows
Python code more than MuJoCo's C, so with it the Python phases' shares are inflated; compare
tables taken the same way, or pass ``--no-cprofile`` for the timers alone.
"""

from __future__ import annotations

import argparse
import os
import pstats
import sys
import tempfile
import time
from collections import defaultdict
from collections.abc import Callable
from multiprocessing import Pool
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine

PHASES = (
    "start-up (imports)",
    "episode load",
    "scene build",
    "physics: mj_step",
    "physics: UAV controller",
    "physics: rest of the loop",
    "IK solves",
    "collision checks",
    "rendering",
    "planning logic (the rest)",
    "worker overhead",
)
_clock = time.thread_time
_spent: defaultdict[str, float] = defaultdict(float)
_stack: list[list[Any]] = []  # [label, seconds spent in nested phases]
_state: dict[str, Any] = {}


def _wrap(owner: Any, name: str, label: str) -> None:
    """Charge ``owner.name``'s CPU, less that of nested phases, to ``label``."""
    inner: Callable[..., Any] = getattr(owner, name)

    def timed(*args: Any, **kwargs: Any) -> Any:
        frame = [label, 0.0]
        _stack.append(frame)
        t0 = _clock()
        try:
            return inner(*args, **kwargs)
        finally:
            spent = _clock() - t0
            _stack.pop()
            _spent[label] += spent - frame[1]
            if _stack:
                _stack[-1][1] += spent

    setattr(owner, name, timed)


def _init(profile: bool, out: str) -> None:
    """Worker start: import and time the executor, install the phase timers."""
    t0 = _clock()
    import mujoco

    from vlm_bench import episodes
    from vlm_bench.executor import live_episode, sim_loop
    from vlm_bench.executor.motion import collision_check, ik
    from vlm_bench.sim import render, uav_control

    _spent["start-up (imports)"] += _clock() - t0
    _wrap(episodes, "get_episode", "episode load")
    _wrap(live_episode, "episode_scene", "scene build")
    _wrap(mujoco, "mj_step", "physics: mj_step")
    _wrap(uav_control.UavController, "apply", "physics: UAV controller")
    _wrap(sim_loop.SimLoop, "control_step", "physics: rest of the loop")
    _wrap(ik.ArmIk, "_solve", "IK solves")
    _wrap(collision_check.CollisionChecker, "collisions", "collision checks")
    _wrap(render.SnapshotRenderer, "render", "rendering")
    _wrap(render.SnapshotRenderer, "render_segmentation", "rendering")
    _wrap(live_episode, "execute_plan", "planning logic (the rest)")
    _state.update(profile=profile, out=out, n=0)


def _one(job: tuple[str, int]) -> dict[str, Any]:
    """Execute one GT plan; the worker's phase CPU since its last report and its stats file."""
    import cProfile

    from vlm_bench import episodes
    from vlm_bench.executor import live_episode

    task, seed = job
    t0 = _clock()
    prof = cProfile.Profile() if _state["profile"] else None
    if prof is not None:
        prof.enable()
    episode = episodes.get_episode(task, seed)
    result = live_episode.execute_plan(episode, episode.gt_plan)
    if prof is not None:
        prof.disable()
    phases = sum(v for k, v in _spent.items() if k != "start-up (imports)")
    _spent["worker overhead"] += _clock() - t0 - phases
    stats = ""
    if prof is not None:
        _state["n"] += 1
        stats = f"{_state['out']}/{os.getpid()}-{_state['n']}.prof"
        prof.dump_stats(stats)
    spent = dict(_spent)
    _spent.clear()
    return {"spent": spent, "stats": stats, "ok": result.exec_success, "sim": result.sim_time_s}


def _seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-9", help="seed range, e.g. 0-9")
    parser.add_argument("--tasks", default="", help="comma-separated task ids (default: all)")
    parser.add_argument("--episodes", default="", help="task:seed list instead of tasks x seeds")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--top", type=int, default=25, help="functions listed by own time")
    parser.add_argument("--sort", default="tottime", help="pstats order, e.g. cumulative")
    parser.add_argument("--only", default="", help="list only functions whose path contains this")
    parser.add_argument("--no-cprofile", action="store_true", help="phase timers only")
    args = parser.parse_args()

    from vlm_bench.catalog.tasks import all_tasks

    tasks = args.tasks.split(",") if args.tasks else [t.id for t in all_tasks()]
    jobs = [(t, s) for s in _seeds(args.seeds) for t in tasks]
    if args.episodes:
        jobs = [(e.rsplit(":", 1)[0], int(e.rsplit(":", 1)[1])) for e in args.episodes.split(",")]
    spent: defaultdict[str, float] = defaultdict(float)
    files: list[str] = []
    ok = sim = 0.0
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        init = (not args.no_cprofile, out)
        with Pool(args.workers, initializer=_init, initargs=init) as pool:
            for row in pool.imap_unordered(_one, jobs):
                for k, v in row["spent"].items():
                    spent[k] += v
                files += [row["stats"]] if row["stats"] else []
                ok, sim = ok + row["ok"], sim + row["sim"]
        wall = time.perf_counter() - t0
        cpu = sum(spent.values())
        print(f"machine: {machine()}")
        print(
            f"{len(jobs)} GT executions, {args.workers} workers, cProfile "
            f"{'off' if args.no_cprofile else 'on'}: {int(ok)}/{len(jobs)} succeeded, "
            f"{sim:.0f} s simulated, {cpu:.1f} s CPU in the workers, {wall:.1f} s wall\n"
        )
        print("| phase | CPU s | share |\n|---|---|---|")
        for phase in PHASES:
            print(f"| {phase} | {spent[phase]:.2f} | {spent[phase] / cpu:.1%} |")
        if files:
            print(f"\nTop {args.top} functions by {args.sort} (cProfile, workers merged):\n")
            stats = pstats.Stats(*files, stream=sys.stdout)
            stats.sort_stats(args.sort).print_stats(*([args.only] if args.only else []), args.top)


if __name__ == "__main__":
    main()
