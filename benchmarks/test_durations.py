"""Which tests the default suite leaves to ``-m slow``: the ones measured over a bound.

Usage: ``pytest -m "" -n 2 --junitxml=durations.xml; python benchmarks/test_durations.py
durations.xml [--over 3.0]``

Reads each test's wall time from a JUnit XML report of the whole suite (``-m ""`` runs the
``slow`` ones too) and writes ``tests/slow_tests.txt``: one node id per line, with its measured
seconds, for every test over ``--over`` seconds that is not already marked ``slow``.
``tests/conftest.py`` marks the listed tests ``slow`` at collection unless they carry the
``smoke`` marker (a test the default suite keeps, whatever its time, because it is the one
that covers a behaviour end to end). Keeps ``.ci/run`` within its time: a suite run under load
(2 cores shared) measures every test about twice as long as an idle one.
"""

from __future__ import annotations

import argparse
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "slow_tests.txt"


def node_id(classname: str, name: str) -> str:
    """The pytest node id of a JUnit test case (``tests.a.test_b[.Class]`` + ``name``)."""
    parts = classname.split(".")
    for cut in range(len(parts), 0, -1):
        path = Path(*parts[:cut]).with_suffix(".py")
        if (ROOT / path).is_file():
            return "::".join([path.as_posix(), *parts[cut:], name])
    raise SystemExit(f"no test file for {classname}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("junit", type=Path, help="JUnit XML of a whole-suite run")
    parser.add_argument("--over", type=float, default=3.0, help="seconds (default 3.0)")
    args = parser.parse_args()
    rows = []
    for case in ET.parse(args.junit).iter("testcase"):
        if case.find("skipped") is not None:
            continue
        seconds = float(case.get("time", "0"))
        if seconds > args.over:
            rows.append((seconds, node_id(case.get("classname", ""), case.get("name", ""))))
    lines = [f"{nid}  # {seconds:.1f} s" for seconds, nid in sorted(rows, key=lambda r: r[1])]
    head = (
        f"# Tests measured over {args.over:g} s, left to -m slow by tests/conftest.py"
        " (benchmarks/test_durations.py).\n"
    )
    OUT.write_text(head + "\n".join(lines) + "\n")
    total = sum(s for s, _ in rows)
    print(f"{len(rows)} tests over {args.over:g} s, {total:.0f} s in all -> {OUT}")


if __name__ == "__main__":
    main()
