"""A whole report from run folders: check everything, compute, then write.

:func:`build_report` reads the runs and computes every table without writing anything, so a bad
column, a missing folder or a missing extra fails before a file appears; :func:`render_tables`
formats the tables and :func:`write_outputs` writes the files (tables, episode frame, plots,
galleries).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import ConfigError, MissingExtraError, UnknownNameError
from vlm_bench.report.bootstrap import bootstrap_cis
from vlm_bench.report.contents import Report
from vlm_bench.report.dataframe import csv_ready
from vlm_bench.report.diagnostics import (
    error_code_table,
    failure_code_table,
    loc_over_blind_run,
    parse_tier_rates,
)
from vlm_bench.report.groups import grouping
from vlm_bench.report.latex_compact import latex_columns
from vlm_bench.report.load import load
from vlm_bench.report.marks import partial_warnings
from vlm_bench.report.names import relabel
from vlm_bench.report.narrow import narrow
from vlm_bench.report.paired import find_system, paired_table
from vlm_bench.report.protocol_notes import protocol_warnings
from vlm_bench.report.render import render_tables
from vlm_bench.report.report_options import ReportOptions
from vlm_bench.report.sections import Section, ci_section, code_section, pair_section, tier_section
from vlm_bench.report.summary import (
    partial_overalls,
    sort_systems,
    summary_long,
    system_order,
)
from vlm_bench.storage.jsonl import write_text_atomic

if TYPE_CHECKING:
    from vlm_bench.report.gallery_views import ViewSources

PAIRED_METRICS = ("S_total", "Succ", "S_loc")
"""Metrics of ``--paired`` (plus ``exec_success`` when both runs executed plans)."""


def _require(package: str, extra: str) -> None:
    if importlib.util.find_spec(package) is None:
        raise MissingExtraError(package, extra)


def _check_extras(options: ReportOptions) -> None:
    parquet = options.format == "parquet" or (
        options.episodes is not None and options.episodes.suffix == ".parquet"
    )
    if parquet:
        _require("pyarrow", "report")
    if options.plots is not None:
        _require("matplotlib", "plots")


def _check_paths(options: ReportOptions) -> None:
    for name, path in (("--out", options.out), ("--episodes", options.episodes)):
        if path is None:
            continue
        if path.is_dir():
            raise ConfigError(f"{name} {path} is a folder; give a file name")
        if not path.parent.is_dir():
            raise ConfigError(f"{name}: folder {path.parent} does not exist")
    for name, path in (("--plots", options.plots), ("--gallery", options.gallery)):
        if path is not None and path.exists() and not path.is_dir():
            raise ConfigError(f"{name} {path} is a file; give a folder")


def _check_by(frame: pd.DataFrame, by: tuple[str, ...]) -> None:
    for column in by:
        if column not in frame.columns:
            raise UnknownNameError("--by column", column, frame.columns)


def build_report(options: ReportOptions) -> Report:
    """Load the runs and compute the report; writes nothing.

    Raises:
        ConfigError / UnknownNameError: A missing run folder, unknown ``--by`` column or
            ``--paired`` system, or an output path that cannot be written.
        MissingExtraError: Parquet without pyarrow, plots without matplotlib.
        BenchmarkVersionError: Runs of different benchmark versions without
            ``mixed_versions``.
    """
    _check_paths(options)
    _check_extras(options)
    frame = load(*options.runs, mixed_versions=options.mixed_versions)
    frame = narrow(frame, options.suites, options.tasks, options.common)
    by = list(options.by)
    _check_by(frame, options.by)
    names = ["suites", "paper"] if options.grouping == "both" else [options.grouping]
    groupings = [grouping(n) for n in names]
    frame = relabel(frame, by, options.labels)  # an unknown --label fails before any file
    if options.paired is not None:
        find_system(frame, by, _paired(options))
    tables = {}
    for g in groupings:
        long = summary_long(frame, by, g)
        tables[g.name] = sort_systems(long, by, g) if options.sort == "total" else long
    if options.format == "latex":
        for g in groupings:
            latex_columns(tables[g.name], options.layout, options.columns)  # checks --columns
    report = Report(options, frame, groupings, tables)
    if options.stats or options.plots is not None:
        for g in groupings:
            report.cis[g.name] = bootstrap_cis(
                frame, by, g, n_boot=options.n_boot, seed=options.seed, level=options.level
            )
    if options.stats:
        _add_sections(report)
    if options.paired is not None:
        _add_paired(report, _paired(options))
    _add_closed_loop(report)
    return report


def _paired(options: ReportOptions) -> str:
    """The ``--paired`` system as the frame names it (its label, where one was given)."""
    assert options.paired is not None
    return options.labels.get(options.paired, options.paired)


def _add_closed_loop(report: Report) -> None:
    """The "Closed loop" sections, where a run is closed-loop."""
    from vlm_bench.report.closed_loop import loop_frame, loop_sections, succ_at_k

    loops = loop_frame(report.frame)
    if loops.empty:
        return
    options = report.options
    report.loop_curve = succ_at_k(loops, options.n_boot, options.seed, options.level)
    report.sections.extend(loop_sections(loops, report.loop_curve))


def _add_sections(report: Report) -> None:
    options, frame, by = report.options, report.frame, list(report.options.by)
    first = report.groupings[0]
    partial = partial_overalls(report.tables[first.name], by)
    report.sections.append(
        ci_section(
            report.cis[first.name], by, first, options.n_boot, options.seed, options.level, partial
        )
    )
    report.sections.append(tier_section(parse_tier_rates(frame, by), by))
    report.sections.append(code_section(error_code_table(frame, by), by))
    failures = failure_code_table(frame, by)
    if not failures.empty:
        report.sections.append(
            code_section(
                failures,
                by,
                "Execution failures",
                "Percent of executed episodes (answered, in runs that execute plans) whose "
                "execution failed, by failure code (no_plan: the answer held no plan to execute).",
            )
        )
    blind = loc_over_blind_run(frame, "run", first, options.n_boot, options.seed)
    if not blind.empty:
        report.sections.append(
            pair_section(
                blind,
                "S_loc above the blind run",
                "Each run's S_loc minus the blind planner's on their common episodes (what the "
                "images add over guessing the likeliest direction), task-clustered interval.",
            )
        )


def _add_paired(report: Report, name: str) -> None:
    options, frame, by = report.options, report.frame, list(report.options.by)
    ok = frame[frame["status"] == "ok"]
    metrics = [*PAIRED_METRICS]
    if "exec_success" in ok.columns and ok["exec_success"].notna().any():
        metrics.append("exec_success")
    pairs = paired_table(
        frame,
        find_system(frame, by, name),
        metrics,
        by,
        report.groupings[0],
        options.n_boot,
        options.seed,
        options.level,
    )
    others = [s for s in system_order(frame, by) if s != find_system(frame, by, name)]
    if not others or not (pairs["n"] > 0).any():
        why = "no other row" if not others else "no episode in common with any other row"
        report.sections.append(
            Section(
                f"Paired comparison with {name}",
                f"Nothing to compare: {why} (--by {','.join(by)} gives the rows; give runs of "
                "other systems over the same episodes).",
                pd.DataFrame({"note": [f"{why} to compare with {name}"]}),
            )
        )
        return
    report.sections.append(
        pair_section(
            pairs,
            f"Paired comparison with {name}",
            "A − B on the episodes both answered: the table's overall estimator with a "
            "task-clustered bootstrap interval, and the exact sign test over tasks (a task's "
            "episodes are not independent: each task counts once, by its mean difference; "
            "the number of tasks is beside each p-value).",
        )
    )


def warnings(report: Report) -> list[str]:
    """What a reader must know beside the numbers: mixed protocols, partial Overalls."""
    by = list(report.options.by)
    partial = [w for g in report.groupings for w in partial_warnings(report.tables[g.name], by, g)]
    return list(dict.fromkeys([*protocol_warnings(report.frame, by), *partial]))


def write_outputs(
    report: Report, tables: str | bytes | None = None, views: ViewSources | None = None
) -> list[Path]:
    """Write the files the options ask for; returns their paths.

    Args:
        report: From :func:`build_report`.
        tables: The rendered tables for ``options.out`` (None: not written here).
        views: The galleries' views (:mod:`vlm_bench.report.gallery_views`; None: no views).
    """
    options = report.options
    written: list[Path] = []
    if options.out is not None and tables is not None:
        if isinstance(tables, bytes):
            options.out.write_bytes(tables)
        else:
            write_text_atomic(options.out, tables)
        written.append(options.out)
    if options.episodes is not None:
        episodes = report.frame
        if options.episodes.suffix == ".parquet":
            episodes.to_parquet(options.episodes, index=False)
        else:
            csv_ready(episodes).to_csv(options.episodes, index=False)
        written.append(options.episodes)
    if options.plots is not None:
        from vlm_bench.report.plots import write_plots

        written.extend(write_plots(report, options.plots))
        if report.loop_curve is not None:
            from vlm_bench.report.closed_loop import plot_succ_at_k

            written.append(plot_succ_at_k(report.loop_curve, options.plots / "succ_at_k.png"))
    if options.gallery is not None:
        from vlm_bench.report.gallery_index import write_galleries

        written.extend(write_galleries(report.frame, options.gallery, options, views))
    return written


def make_report(
    options: ReportOptions, views: ViewSources | None = None
) -> tuple[Report, list[Path]]:
    """Build the report and write its files (``options.out`` gets the formatted tables); a
    gallery's views come from ``views`` (e.g. :func:`vlm_bench.runner.run_views.run_views`)."""
    report = build_report(options)
    tables = render_tables(report) if options.out is not None else None
    return report, write_outputs(report, tables, views)
