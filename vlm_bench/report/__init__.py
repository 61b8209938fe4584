"""Reports from ``results/`` only: records as DataFrames, the paper's tables, statistics.

``load(*runs)`` gives one tidy row per episode; the table functions take any such frame. Plots
(:mod:`vlm_bench.report.plots`, the ``plots`` extra) and HTML galleries
(:mod:`vlm_bench.report.gallery`) are imported from their modules.
"""

from vlm_bench.report.bootstrap import bootstrap_cis
from vlm_bench.report.dataframe import load_records_frame, records_frame
from vlm_bench.report.diagnostics import (
    error_code_frequencies,
    failure_code_frequencies,
    failure_code_table,
    loc_over_blind_run,
    parse_tier_rates,
)
from vlm_bench.report.groups import grouping, paper_grouping
from vlm_bench.report.load import DERIVED, SETTINGS, load
from vlm_bench.report.make import build_report
from vlm_bench.report.paired import paired_comparison, paired_table, sign_test
from vlm_bench.report.render import render_tables
from vlm_bench.report.report_options import report_options
from vlm_bench.report.summary import EXEC_VALUES, SUMMARY_COLUMNS, summary_long, summary_wide
from vlm_bench.report.tables import summary_markdown, summary_rich, write_summary

__all__ = [
    "DERIVED",
    "EXEC_VALUES",
    "SETTINGS",
    "SUMMARY_COLUMNS",
    "bootstrap_cis",
    "build_report",
    "error_code_frequencies",
    "failure_code_frequencies",
    "failure_code_table",
    "grouping",
    "load",
    "load_records_frame",
    "loc_over_blind_run",
    "paired_comparison",
    "paired_table",
    "paper_grouping",
    "parse_tier_rates",
    "records_frame",
    "render_tables",
    "report_options",
    "sign_test",
    "summary_long",
    "summary_markdown",
    "summary_rich",
    "summary_wide",
    "write_summary",
]
