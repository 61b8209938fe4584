"""Generation and plan executions overlapped: a run's wall time against max(generation, execution).

Usage: ``python benchmarks/overlap.py [--latency 2] [--batch-size 2] [--tasks 8] [--seeds 1]
[--workers 1,2] [--closed --perturb slip=0.5]``

A mock backend answers every batch after a fixed ``--latency`` (like a model on a GPU) with the
GT plans. For each number of execution workers, three runs over the same episodes (explicit
instruction, seeds 0 to ``--seeds`` − 1; snapshots cached beforehand, so rendering is out of the
picture):

* generation: ``--no-execute`` with the latency (what the model alone takes);
* execution: the plans executed with no latency (what the simulator alone takes);
* both: the run as a user makes it.

Overlap is perfect when *both* takes max(generation, execution); serial executions take their sum.
All runs of one invocation are measured on the same machine state; the ratios are what to quote.

``--closed``: closed-loop runs of the ``rules`` planner (scene as text) with ``--perturb`` on
tasks that fly with an object in the hand, so that rounds fail and replans interleave with
other episodes' executions. A closed loop cannot
generate without executing, so *generation* is the batches the *both* run asked for times the
latency.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import ClassVar

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

from _machine import machine

from vlm_bench.backends.builtin import OracleBackend
from vlm_bench.backends.rules_planner import RulesBackend
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

CARRY_TASKS = (
    "place_on_flat_surface",
    "deformable_object_banana",
    "tool_manipulation_mug",
    "cylinder_manipulation",
    "variant_banana_in_box",
    "variant_meat_can_in_box",
)
"""Tasks whose GT flies with an object in the hand (slips happen there: closed loop)."""


class _Slow:
    """A built-in planner answering each batch after ``latency`` seconds (mixed in first)."""

    name: ClassVar[str]

    def __init__(self, latency: float) -> None:
        super().__init__(self.name)  # type: ignore[call-arg]
        self.latency = latency

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        time.sleep(self.latency)
        return super().generate(requests, config)  # type: ignore[misc,no-any-return]


class SlowOracle(_Slow, OracleBackend):
    """The oracle, answering each batch after ``latency`` seconds."""

    name = "oracle"


class SlowRules(_Slow, RulesBackend):
    """The rules planner, answering each batch after ``latency`` seconds."""

    name = "rules"


def _run(
    tasks: Sequence[str],
    seeds: int,
    out: Path,
    cache: Path,
    latency: float,
    batch: int,
    execute: bool,
    workers: int,
    perturb: str | None = None,
) -> tuple[float, int]:
    """Wall time and generate calls of one run (closed loop where ``perturb`` is given)."""
    import vlm_bench
    from vlm_bench.types.execution import ExecutionOptions

    closed = {"loop": "closed", "perturb": perturb, "scene_as_text": True} if perturb else {}
    backend = SlowRules(latency) if perturb else SlowOracle(latency)
    start = time.perf_counter()
    result = vlm_bench.run(
        model=backend.name,
        tasks=tuple(tasks),
        seeds=tuple(range(seeds)),
        instructions=("explicit",),
        execute=execute,
        generation=GenerationConfig(batch_size=batch),
        out=out,
        backend=backend,
        snapshot_cache=cache,
        execution=ExecutionOptions(workers=workers),
        **closed,
    )
    return time.perf_counter() - start, result.stats.generate_calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--latency", type=float, default=2.0, help="seconds per batch")
    parser.add_argument("--batch-size", type=int, default=2)
    parser.add_argument("--tasks", type=int, default=8, help="episodes (fast GT executions)")
    parser.add_argument("--seeds", type=int, default=1, help="seeds per task (0 .. N-1)")
    parser.add_argument("--workers", default="1,2", help="execution workers to compare")
    parser.add_argument("--closed", action="store_true", help="closed loop (rules planner)")
    parser.add_argument("--perturb", default="slip=0.5", help="closed loop: --perturb")
    args = parser.parse_args()
    if args.closed:
        closed_loop(args)
        return
    tasks = FAST_TASKS[: args.tasks]
    print(machine())
    n = len(tasks) * args.seeds
    print(f"{n} episodes, batch {args.batch_size}, {args.latency} s per batch")
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        cache = root / "snapshots"
        _run(tasks, args.seeds, root / "warm", cache, 0.0, args.batch_size, False, 0)  # render once
        gen, _ = _run(
            tasks, args.seeds, root / "gen", cache, args.latency, args.batch_size, False, 0
        )
        print(f"generation alone: {gen:.1f} s")
        print("| workers | generation s | execution s | both s | both / max | both / sum |")
        print("|---|---|---|---|---|---|")
        for workers in (int(w) for w in args.workers.split(",")):
            exe, _ = _run(
                tasks,
                args.seeds,
                root / f"exe{workers}",
                cache,
                0.0,
                args.batch_size,
                True,
                workers,
            )
            both, _ = _run(
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


def closed_loop(args: argparse.Namespace) -> None:
    """The closed-loop table: generation = the both run's batches x latency (module doc)."""
    tasks = CARRY_TASKS[: args.tasks]
    print(machine())
    n = len(tasks) * args.seeds
    print(f"{n} closed-loop episodes, --perturb {args.perturb}, batch {args.batch_size}, ")
    print(f"{args.latency} s per batch")
    print("| workers | generation s | execution s | both s | both / max | both / sum |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        root, batch = Path(tmp), args.batch_size
        cache = root / "snapshots"
        _run(tasks, args.seeds, root / "warm", cache, 0.0, batch, False, 0)  # render once
        for workers in (int(w) for w in args.workers.split(",")):
            exe, _ = _run(
                tasks,
                args.seeds,
                root / f"e{workers}",
                cache,
                0.0,
                batch,
                True,
                workers,
                args.perturb,
            )
            both, calls = _run(
                tasks,
                args.seeds,
                root / f"b{workers}",
                cache,
                args.latency,
                batch,
                True,
                workers,
                args.perturb,
            )
            gen = calls * args.latency
            print(
                f"| {workers} | {gen:.1f} | {exe:.1f} | {both:.1f} | "
                f"{both / max(gen, exe):.2f} | {both / (gen + exe):.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
