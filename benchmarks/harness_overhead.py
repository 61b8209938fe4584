"""Per-episode harness overhead: everything a run does except the model.

Runs the oracle backend (answers instantly) through the full pipeline (episode build, snapshot
render or cache read, PNG encoding, prompt, request, parse, score, durable record and response
writes) twice into fresh run folders: once with an empty snapshot cache (renders every episode)
and once with the cache filled by the first pass (what reruns and other models see). Prints
ms/episode for both, a per-stage breakdown of the uncached pass, and the machine.

Usage:
    python benchmarks/harness_overhead.py [--tasks 12] [--seeds 0-1] [--resolution 448]
"""

from __future__ import annotations

import argparse
import cProfile
import os
import platform
import pstats
import shutil
import tempfile
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.cli.options import parse_seeds
from vlm_bench.runner import run_benchmark
from vlm_bench.types.run import RunConfig

STAGES = {
    "episode build": ("generate.py", "make_episode"),
    "render (scene + views)": ("snapshot_render.py", "render_episode"),
    "PNG encoding": ("png.py", "to_png"),
    "prompt": ("builder.py", "build_prompt"),
    "parse": ("parser.py", "parse_plan"),
    "score": ("metrics.py", "score_plan"),
    "record/response writes": ("jsonl.py", "append"),
}


def cpu_model() -> str:
    """CPU model name from /proc/cpuinfo (or the platform's processor string)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def timed_run(
    config: RunConfig, root: Path, cache: Path, profile: bool
) -> tuple[float, pstats.Stats | None]:
    """Seconds for one run of ``config`` into a fresh folder (optionally profiled)."""
    profiler = cProfile.Profile() if profile else None
    start = time.perf_counter()
    if profiler is not None:
        profiler.enable()
    run_benchmark(config, root, snapshot_cache=cache, progress=False)
    if profiler is not None:
        profiler.disable()
    elapsed = time.perf_counter() - start
    return elapsed, pstats.Stats(profiler) if profiler is not None else None


def stage_ms(stats: pstats.Stats, n: int) -> dict[str, float]:
    """Cumulative ms/episode spent in each stage's entry function (profiler overhead included)."""
    totals = dict.fromkeys(STAGES, 0.0)
    table = stats.stats  # type: ignore[attr-defined]
    for (file, _line, func), (_cc, _nc, _tt, cumulative, _callers) in table.items():
        for stage, (name, entry) in STAGES.items():
            if Path(file).name == name and func == entry:
                totals[stage] += cumulative
    return {stage: 1000.0 * t / n for stage, t in totals.items()}


def main() -> None:
    """Parse options, run both passes, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", type=int, default=12, help="First N tasks (spread suites).")
    parser.add_argument("--seeds", default="0-1")
    parser.add_argument("--resolution", type=int, default=448)
    args = parser.parse_args()
    tasks = all_tasks()
    step = max(1, len(tasks) // args.tasks)
    chosen = tuple(t.id for t in tasks[::step][: args.tasks])
    config = RunConfig(
        model="oracle",
        tasks=chosen,
        seeds=tuple(parse_seeds(args.seeds)),
        resolution=args.resolution,
        execute=False,  # plan execution is simulation time, not harness overhead
    )
    n = len(chosen) * len(config.seeds) * len(config.instructions)
    scenes = len(chosen) * len(config.seeds)
    work = Path(tempfile.mkdtemp(prefix="vlm-bench-overhead-"))
    try:
        cache = work / "snapshots"
        cold, stats = timed_run(config, work / "cold", cache, profile=False)
        _, stats = timed_run(config, work / "profiled", work / "snapshots-2", profile=True)
        warm, _ = timed_run(config, work / "warm", cache, profile=False)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(
        f"machine: {cpu_model()}, {os.cpu_count()} cores, {platform.system()} "
        f"{platform.machine()}, MUJOCO_GL={os.environ.get('MUJOCO_GL')}"
    )
    print(
        f"episodes: {n} ({len(chosen)} tasks x {len(config.seeds)} seeds x 2 instructions; "
        f"{scenes} scenes), views: {len(config.views)} at {config.resolution} px, "
        "backend: oracle"
    )
    print(
        f"uncached snapshots: {1000 * cold / n:8.1f} ms/episode  (total {cold:.2f} s, "
        "includes GL context creation)"
    )
    print(f"cached snapshots:   {1000 * warm / n:8.1f} ms/episode  (total {warm:.2f} s)")
    if stats is not None:
        print("uncached breakdown (profiled run, ms/episode, cumulative):")
        for stage, ms in stage_ms(stats, n).items():
            print(f"  {stage:<24}{ms:8.2f}")


if __name__ == "__main__":
    main()
