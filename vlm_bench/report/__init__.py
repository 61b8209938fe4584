"""Reports from ``results/`` only: records as DataFrames, the paper's tables, statistics.

``load(*runs)`` gives one tidy row per episode; the table functions take any such frame. Plots
(:mod:`vlm_bench.report.plots`, the ``plots`` extra) and HTML galleries
(:mod:`vlm_bench.report.gallery`) are imported from their modules.
"""

from vlm_bench.report.bootstrap import bootstrap_cis
from vlm_bench.report.contents import Report
from vlm_bench.report.dataframe import (
    COLUMNS,
    EXEC_METRICS,
    METRICS,
    load_records_frame,
    records_frame,
)
from vlm_bench.report.diagnostics import (
    error_code_frequencies,
    error_code_table,
    failure_code_frequencies,
    failure_code_table,
    loc_over_blind_run,
    parse_tier_rates,
)
from vlm_bench.report.groups import SUITES, Grouping, grouping, paper_columns, paper_grouping
from vlm_bench.report.latex import latex_document, summary_latex
from vlm_bench.report.load import DERIVED, SETTINGS, load
from vlm_bench.report.make import build_report, make_report, render_tables
from vlm_bench.report.paired import PairedComparison, paired_comparison, paired_table, sign_test
from vlm_bench.report.report_options import ReportOptions, report_options
from vlm_bench.report.summary import (
    BOTH,
    EXEC_VALUES,
    OVERALL,
    SUMMARY_COLUMNS,
    sort_systems,
    summary_long,
    summary_wide,
)
from vlm_bench.report.tables import summary_markdown, summary_rich, write_summary

__all__ = [
    "BOTH",
    "COLUMNS",
    "DERIVED",
    "EXEC_METRICS",
    "EXEC_VALUES",
    "METRICS",
    "OVERALL",
    "SETTINGS",
    "SUITES",
    "SUMMARY_COLUMNS",
    "Grouping",
    "PairedComparison",
    "Report",
    "ReportOptions",
    "bootstrap_cis",
    "build_report",
    "error_code_frequencies",
    "error_code_table",
    "failure_code_frequencies",
    "failure_code_table",
    "grouping",
    "latex_document",
    "load",
    "load_records_frame",
    "loc_over_blind_run",
    "make_report",
    "paired_comparison",
    "paired_table",
    "paper_columns",
    "paper_grouping",
    "parse_tier_rates",
    "records_frame",
    "render_tables",
    "report_options",
    "sign_test",
    "sort_systems",
    "summary_latex",
    "summary_long",
    "summary_markdown",
    "summary_rich",
    "summary_wide",
    "write_summary",
]
