"""Replay every whole-execution episode of a demos export in the gym environment and report
the share that reproduces its success (docs/demos.md#replay).

Usage::

    python benchmarks/demos_replay.py DATASET [--limit N]

Prints one line per episode and a JSON summary.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from vlm_bench.vla.demos.reader import DemoDataset
from vlm_bench.vla.demos.replay import replay_episode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dataset", type=Path)
    parser.add_argument("--limit", type=int, default=None, help="Replay the first N episodes.")
    args = parser.parse_args()
    data = DemoDataset(args.dataset)
    indices = range(len(data) if args.limit is None else min(args.limit, len(data)))
    t0 = time.perf_counter()
    results = []
    for index in indices:
        r = replay_episode(data, index)
        results.append(r)
        print(f"{index} {r.task_id}/{r.seed} success={r.success} state_err={r.max_state_error:.4f}")
    ok = sum(r.success for r in results)
    print(
        json.dumps(
            {
                "replayed": len(results),
                "success": ok,
                "rate": ok / len(results) if results else None,
                "seconds": round(time.perf_counter() - t0, 1),
            }
        )
    )


if __name__ == "__main__":
    main()
