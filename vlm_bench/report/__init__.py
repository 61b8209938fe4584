"""Reports from ``results/`` only: records as DataFrames, the paper's summary table."""

from vlm_bench.report.frame import (
    COLUMNS,
    EXEC_METRICS,
    METRICS,
    load_records_frame,
    records_frame,
)
from vlm_bench.report.summary import (
    BOTH,
    EXEC_VALUES,
    OVERALL,
    SUMMARY_COLUMNS,
    summary_long,
    summary_wide,
)
from vlm_bench.report.tables import summary_markdown, summary_rich, write_summary

__all__ = [
    "BOTH",
    "COLUMNS",
    "EXEC_METRICS",
    "EXEC_VALUES",
    "METRICS",
    "OVERALL",
    "SUMMARY_COLUMNS",
    "load_records_frame",
    "records_frame",
    "summary_long",
    "summary_markdown",
    "summary_rich",
    "summary_wide",
    "write_summary",
]
