"""Scene compile time, physics steps/s and render ms per view (224² and 448²).

Usage: python benchmarks/sim_speed.py [--repeats N]
Runs one household, one industrial and one outdoor task at seed 0.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import mujoco
from _machine import machine

from vlm_bench.catalog.tasks import get_task
from vlm_bench.episodes import make_episode
from vlm_bench.sim.constants import CAMERAS
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import build_scene, build_spec

TASKS = {
    "household": "standard_pick_place",
    "industrial": "variant_green_nut",
    "outdoor": "place_on_flat_surface",
}


def _ms(fn: object, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()  # type: ignore[operator]
        times.append((time.perf_counter() - t0) * 1000)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"machine: {machine()}")
    print(
        f"{'scene':<11} {'task':<24} {'build spec':>10} {'compile':>8} {'steps/s':>9} "
        f"{'224² ms':>8} {'448² ms':>8}"
    )
    renderer = SnapshotRenderer()
    for env_type, task_id in TASKS.items():
        ep = make_episode(get_task(task_id), 0)
        assert get_task(task_id).environment.startswith(env_type)
        build_ms = _ms(lambda ep=ep: build_spec(ep), args.repeats)
        spec = build_spec(ep)
        compile_ms = _ms(spec.compile, args.repeats)
        scene = build_scene(ep)
        n = 2000
        t0 = time.perf_counter()
        for _ in range(n):
            scene.controller.apply(scene.data)
            mujoco.mj_step(scene.model, scene.data)
        steps = n / (time.perf_counter() - t0)
        render = {}
        for size in (224, 448):
            renderer.render_views(scene.model, scene.data, CAMERAS, size)  # warm-up
            render[size] = _ms(
                lambda s=size, sc=scene: renderer.render_views(sc.model, sc.data, CAMERAS, s),
                args.repeats,
            ) / len(CAMERAS)
        print(
            f"{env_type:<11} {task_id:<24} {build_ms:>8.1f}ms {compile_ms:>6.1f}ms "
            f"{steps:>9.0f} {render[224]:>8.1f} {render[448]:>8.1f}"
        )
    renderer.close()


if __name__ == "__main__":
    main()
