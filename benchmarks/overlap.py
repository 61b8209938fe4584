"""Generation and plan replays overlapped: a run's wall time against max(generation, execution).

Usage: ``python benchmarks/overlap.py [--latency 2] [--batch-size 2] [--tasks 8] [--seeds 1]
[--workers 1,2]``

A mock backend answers every batch after a fixed ``--latency`` (like a model on a GPU) with the
GT plans. For each number of replay workers, three runs over the same episodes (explicit
instruction, seeds 0 to ``--seeds`` − 1; snapshots cached beforehand, so rendering is out of the
picture):

* generation: ``--no-execute`` with the latency (what the model alone takes);
* execution: the plans replayed with no latency (what the simulator alone takes);
* both: the run as a user makes it.

Overlap is perfect when *both* takes max(generation, execution); serial replays take their sum.
All runs of one invocation are measured on the same machine state; the ratios are what to quote.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine

from vlm_bench.backends.builtin import OracleBackend
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

FAST_TASKS = (
    "container_geometry_bowl",
    "slim_object_in_bowl",
    "clear_desk_push_box",
    "spatial_ref_middle_drawer",
    "variant_teddy_bear",
    "variant_chocolate_box",
    "irregular_on_plate",
    "stacking_can_on_wood",
    "assembly_camera_on_lidar",
    "spatial_ref_top_drawer",
)


class SlowOracle(OracleBackend):
    """The oracle, answering each batch after ``latency`` seconds."""

    name = "oracle"

    def __init__(self, latency: float) -> None:
        super().__init__("oracle")
        self.latency = latency

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        time.sleep(self.latency)
        return super().generate(requests, config)


def _run(
    tasks: Sequence[str],
    seeds: int,
    out: Path,
    cache: Path,
    latency: float,
    batch: int,
    execute: bool,
    workers: int,
) -> float:
    import vlm_bench
    from vlm_bench.types.execution import ReplayOptions

    start = time.perf_counter()
    vlm_bench.run(
        model="oracle",
        tasks=tuple(tasks),
        seeds=tuple(range(seeds)),
        instructions=("explicit",),
        execute=execute,
        generation=GenerationConfig(batch_size=batch),
        out=out,
        backend=SlowOracle(latency),
        snapshot_cache=cache,
        replay=ReplayOptions(workers=workers),
    )
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--latency", type=float, default=2.0, help="seconds per batch")
    parser.add_argument("--batch-size", type=int, default=2)
    parser.add_argument("--tasks", type=int, default=8, help="episodes (fast GT replays)")
    parser.add_argument("--seeds", type=int, default=1, help="seeds per task (0 .. N-1)")
    parser.add_argument("--workers", default="1,2", help="replay workers to compare")
    args = parser.parse_args()
    tasks = FAST_TASKS[: args.tasks]
    print(machine())
    n = len(tasks) * args.seeds
    print(f"{n} episodes, batch {args.batch_size}, {args.latency} s per batch")
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        cache = root / "snapshots"
        _run(tasks, args.seeds, root / "warm", cache, 0.0, args.batch_size, False, 0)  # render once
        gen = _run(tasks, args.seeds, root / "gen", cache, args.latency, args.batch_size, False, 0)
        print(f"generation alone: {gen:.1f} s")
        print("| workers | generation s | execution s | both s | both / max | both / sum |")
        print("|---|---|---|---|---|---|")
        for workers in (int(w) for w in args.workers.split(",")):
            exe = _run(
                tasks,
                args.seeds,
                root / f"exe{workers}",
                cache,
                0.0,
                args.batch_size,
                True,
                workers,
            )
            both = _run(
                tasks,
                args.seeds,
                root / f"both{workers}",
                cache,
                args.latency,
                args.batch_size,
                True,
                workers,
            )
            print(
                f"| {workers} | {gen:.1f} | {exe:.1f} | {both:.1f} | "
                f"{both / max(gen, exe):.2f} | {both / (gen + exe):.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
