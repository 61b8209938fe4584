"""What a report shows: :class:`Report`, computed by :mod:`vlm_bench.report.make` and drawn by
:mod:`vlm_bench.report.plots` (its own module, so neither of the two imports the other)."""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.groups import Grouping
from vlm_bench.report.report_options import ReportOptions
from vlm_bench.report.sections import Section


@dataclass
class Report:
    """Everything a report shows, computed from the runs' records."""

    options: ReportOptions
    frame: pd.DataFrame
    """One row per episode (:func:`vlm_bench.report.load`)."""
    groupings: list[Grouping]
    tables: dict[str, pd.DataFrame]
    """Long summary per grouping name (:func:`vlm_bench.report.summary.summary_long`)."""
    cis: dict[str, pd.DataFrame] = field(default_factory=dict)
    """Bootstrap intervals per grouping name (with ``stats``)."""
    sections: list[Section] = field(default_factory=list)
    """Statistics as display tables, in order."""
    loop_curve: pd.DataFrame | None = None
    """Succ@k of the closed-loop runs (:mod:`vlm_bench.report.closed_loop`), if any."""
