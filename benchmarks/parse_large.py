"""Parsing time of pathological one-megabyte model outputs (the bound on work per answer).

Each shape is a way a looping or broken model fills its token budget: a plan repeated, a
megabyte-long plan, unclosed brackets, JSON lines, Python reprs, deep nesting, prose. Prints
seconds per shape (best of ``--repeat``), the parse tier and codes, and the machine.

Usage:
    python benchmarks/parse_large.py [--size 1000000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

from _machine import machine

from vlm_bench.parsing import parse_plan

STEP = '{"tasktype": "ARM", "skill": "pick", "object": "red_cup_1"}'
IDS = ["red_cup_1", "yellow_basket"]


def _fill(piece: str, size: int) -> str:
    return (piece * (size // len(piece) + 1))[:size]


def shapes(size: int) -> dict[str, str]:
    """The outputs timed, each ``size`` characters long (about)."""
    return {
        "prose": _fill("the drone flies up and then picks the cup. ", size),
        "plan repeated": _fill("[" + STEP + "]\n", size),
        "one long plan": "[" + ",".join([STEP] * (size // (len(STEP) + 1))) + "]",
        "open brackets": _fill("[", size),
        "open objects": _fill('{"a": ', size),
        "steps, unclosed": "[" + _fill(STEP + ",", size),
        "quotes": _fill('"', size),
        "unfinished steps": _fill('[{"tasktype": "UAV", "direction": "up" ', size),
        "one string": '"' + _fill("a", size) + '"',
        "JSON lines": _fill(STEP + "\n", size),
        "unclosed think": "<think>" + _fill("hmm [ { ", size),
        "code fences": _fill("```json\n[" + STEP + "\n```\n", size),
        "Python repr": _fill("[{'tasktype': 'ARM', 'skill': 'pick', 'object': 'x'}, ", size),
        "keys without quotes": _fill("{a:[b:{c:", size),
        "deep nesting": "[" * (size // 2) + "]" * (size // 2),
        "numbers": "[" + _fill("1,", size) + "1]",
        "huge integer": '[{"tasktype": "UAV", "direction": "up", "distance": ' + "9" * size + "}]",
        "plan then loop": "[" + STEP + "]\n" + _fill("and again I fly up. ", size),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1_000_000, help="characters per output")
    parser.add_argument("--repeat", type=int, default=3, help="runs per shape (best is kept)")
    args = parser.parse_args()
    print(machine())
    print(f"{'shape':22s} {'seconds':>8s}  result")
    worst = 0.0
    for name, text in shapes(args.size).items():
        best = float("inf")
        for _ in range(args.repeat):
            start = time.perf_counter()
            result = parse_plan(text, IDS)
            best = min(best, time.perf_counter() - start)
        worst = max(worst, best)
        codes = ",".join(str(c) for c in result.errors) or "-"
        repairs = ",".join(str(r) for r in result.repairs) or "-"
        print(f"{name:22s} {best:8.3f}  {result.tier} [{codes}] ({repairs}) {result.n_steps} steps")
    print(f"slowest: {worst:.3f} s")


if __name__ == "__main__":
    main()
