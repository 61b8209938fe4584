"""Run a benchmark's jobs in worker processes, writing each result as it finishes."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Iterator
from multiprocessing import Pool
from pathlib import Path
from typing import Any, TypeVar

Job = TypeVar("Job")


def pooled_rows(
    one: Callable[[Job], dict[str, Any]], jobs: Iterable[Job], workers: int, out: Path | None
) -> list[dict[str, Any]]:
    """``one`` applied to every job, in ``workers`` processes (in this one for a single worker),
    in the order they finish; with ``out``, one JSON line per finished job, flushed as it comes,
    so a long sweep can be watched."""
    rows: list[dict[str, Any]] = []
    sink = out.open("w") if out is not None else None
    pool = Pool(workers) if workers > 1 else None
    results: Iterator[dict[str, Any]] = (
        pool.imap_unordered(one, jobs) if pool is not None else map(one, jobs)
    )
    try:
        for row in results:
            rows.append(row)
            if sink is not None:
                sink.write(json.dumps(row) + "\n")
                sink.flush()
    finally:
        if pool is not None:
            pool.close()
            pool.join()
        if sink is not None:
            sink.close()
    return rows
