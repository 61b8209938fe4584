"""Compare the records of two run folders field by field, leaving out what a run's timing and
identity change (wall time, latency, run id, creation time): a refactor's runs must be equal.

    python benchmarks/compare_records.py BEFORE_DIR AFTER_DIR [--common]

``--common`` compares only the episodes both folders hold (runs still in progress). Exits 1 where
an episode differs, naming the first differing fields.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

TIMING = {"wall_time_s", "latency_s", "run_id", "created"}


def _strip(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k not in TIMING}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _records(folder: Path) -> dict[str, Any]:
    rows = [json.loads(line) for line in (folder / "records.jsonl").read_text().splitlines()]
    return {row["key"]: _strip(row) for row in rows if line_ok(row)}


def line_ok(row: dict[str, Any]) -> bool:
    """A finished record (errors are retried by a resume, not compared)."""
    return row.get("status") == "ok"


def _diff(a: Any, b: Any, path: str = "") -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        out: list[str] = []
        for key in sorted(set(a) | set(b)):
            out += _diff(a.get(key), b.get(key), f"{path}.{key}" if path else key)
        return out
    return [] if a == b else [path]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--common", action="store_true", help="only episodes both folders hold")
    args = parser.parse_args()
    before, after = _records(args.before), _records(args.after)
    keys = sorted(set(before) & set(after)) if args.common else sorted(set(before) | set(after))
    differing = 0
    for key in keys:
        if key not in before or key not in after:
            print(f"{key}: only in {'after' if key in after else 'before'}")
            differing += 1
            continue
        fields = _diff(before[key], after[key])
        if fields:
            differing += 1
            print(f"{key}: {', '.join(fields[:6])}")
    print(f"{len(keys) - differing} of {len(keys)} episodes equal in every field but timing")
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
