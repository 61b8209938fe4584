"""``vlm-bench report``: the paper's tables, statistics, plots and galleries from run folders.

A thin layer over :mod:`vlm_bench.report.make`: every option is checked and every run read
before a file is written.
"""

from __future__ import annotations

import io
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.console import Console

from vlm_bench.cli.options import PIPE_WIDTH, table_console

if TYPE_CHECKING:
    from vlm_bench.report.contents import Report

console = Console()
"""Width of the tables when stdout is no terminal (a pipe or file), as with ``--out``."""


def _split(text: str) -> tuple[str, ...]:
    return tuple(part.strip() for part in text.split(",") if part.strip())


def report(
    runs: Annotated[
        list[str], typer.Argument(metavar="RUN...", help="Run folders or glob patterns.")
    ],
    by: Annotated[
        str,
        typer.Option(help="Episode column(s) naming a row, comma-separated (views,resolution)."),
    ] = "model",
    grouping: Annotated[
        str, typer.Option(help="Column groups: suites, paper (the paper's 3 columns) or both.")
    ] = "both",
    format: Annotated[
        str, typer.Option("--format", "-f", help="terminal, markdown, csv, parquet or latex.")
    ] = "terminal",
    out: Annotated[Path | None, typer.Option(help="Write the tables to this file.")] = None,
    standalone: Annotated[
        bool, typer.Option("--standalone", help="LaTeX: a whole document (pdflatex-ready).")
    ] = False,
    fit_width: Annotated[
        bool, typer.Option("--fit-width", help="LaTeX: scale each table to the text width.")
    ] = False,
    layout: Annotated[
        str,
        typer.Option(
            help="LaTeX: paper (the paper's full table), column (fits \\columnwidth) or wide "
            "(fits a two-column table*), the last two unscaled."
        ),
    ] = "paper",
    columns: Annotated[
        str | None,
        typer.Option(help="LaTeX: the metrics shown, comma-separated (Tot,Succ,Exec,Loc,...)."),
    ] = None,
    label: Annotated[
        list[str] | None,
        typer.Option(
            metavar="RUN=NAME",
            help="Display name for a run or row value (repeatable), in every table, plot and "
            "gallery; LaTeX rows default to the model card's name.",
        ),
    ] = None,
    suite: Annotated[
        list[str] | None, typer.Option(help="Only episodes of this suite (repeatable; e.g. lh).")
    ] = None,
    task: Annotated[
        list[str] | None, typer.Option(help="Only episodes of this task (repeatable).")
    ] = None,
    common: Annotated[
        bool,
        typer.Option("--common", help="Only the episodes every run has (comparable rows)."),
    ] = False,
    sort: Annotated[str, typer.Option(help="Row order: given, or total (overall Tot).")] = "given",
    stats: Annotated[
        bool, typer.Option("--stats/--no-stats", help="Intervals, parse tiers, error codes.")
    ] = True,
    paired: Annotated[
        str | None,
        typer.Option(
            help="Compare every other row with this one (a value of --by) on common episodes."
        ),
    ] = None,
    episodes: Annotated[
        Path | None, typer.Option(help="Also write the per-episode frame (.csv or .parquet).")
    ] = None,
    plots: Annotated[Path | None, typer.Option(help="Write PNG plots into this folder.")] = None,
    gallery: Annotated[
        Path | None, typer.Option(help="Write an HTML gallery per run into this folder.")
    ] = None,
    inline_images: Annotated[
        bool, typer.Option("--inline-images", help="Gallery: one file, images inside.")
    ] = False,
    render: Annotated[
        bool,
        typer.Option("--render/--no-render", help="Gallery: render views the cache lacks."),
    ] = True,
    n_boot: Annotated[
        int, typer.Option(help="Bootstrap replicates.")
    ] = 2000,  # = ReportOptions (a test holds them equal)
    seed: Annotated[int, typer.Option(help="Bootstrap seed.")] = 0,  # = ReportOptions
    mixed_versions: Annotated[
        bool,
        typer.Option(
            "--mixed-versions", help="Put runs of different benchmark versions in one table."
        ),
    ] = False,
) -> None:
    """Print the paper's VLM table (and statistics) for saved runs; write LaTeX, CSV, plots."""
    from vlm_bench.cli.options import parse_suite
    from vlm_bench.report.make import build_report, warnings, write_outputs
    from vlm_bench.report.names import parse_labels
    from vlm_bench.report.render import render_tables
    from vlm_bench.report.report_options import report_options
    from vlm_bench.report.results_table import print_results_files, standalone_results

    files = standalone_results(runs)
    if files:  # results.json files on their own: their summary table
        print_results_files(files, format, out)
        return

    options = report_options(
        runs=tuple(runs),
        by=_split(by),
        grouping=grouping,
        format=format,
        out=out,
        standalone=standalone,
        fit_width=fit_width,
        layout=layout,
        columns=_split(columns or ""),
        labels=parse_labels(tuple(label or ())),
        suites=tuple(str(parse_suite(s)) for s in suite or ()),
        tasks=tuple(task or ()),
        common=common,
        sort=sort,
        stats=stats,
        paired=paired,
        episodes=episodes,
        plots=plots,
        gallery=gallery,
        inline_images=inline_images,
        render_missing=render,
        n_boot=n_boot,
        seed=seed,
        mixed_versions=mixed_versions,
    )
    result = build_report(options)
    tables: str | bytes | None = None
    if options.format != "terminal":
        tables = render_tables(result)
    elif options.out is not None:
        buffer = io.StringIO()
        _print_terminal(result, Console(file=buffer, width=PIPE_WIDTH, color_system=None))
        tables = buffer.getvalue()
    else:
        _print_terminal(result, table_console(console))
    if options.out is None and isinstance(tables, str):
        sys.stdout.write(tables)
    if options.format != "terminal" or options.out is not None:
        for warning in warnings(result):
            print(f"warning: {warning}", file=sys.stderr)
    views = None
    if options.gallery is not None:  # reports read run folders only: the views come from here
        from vlm_bench.runner.run_views import run_views

        views = run_views(options.render_missing)
    for path in write_outputs(result, tables, views):
        print(f"wrote {path}", file=sys.stderr)
    _warn_torn(options.runs)


def _warn_torn(runs: tuple[str, ...]) -> None:
    """Name the runs whose records file ends in a torn line (its episode is not reported)."""
    from vlm_bench.report.load import resolve_runs
    from vlm_bench.storage import RunPaths, torn_tail

    for run_dir in resolve_runs(runs):
        records = RunPaths(run_dir).records
        torn = torn_tail(records)
        if torn:
            print(
                f"warning: {records} ends in a torn line ({torn} bytes, a crash mid-write): "
                "that episode is not in the report; re-run its run command to resume it",
                file=sys.stderr,
            )


def _print_terminal(result: Report, target: Console) -> None:
    from vlm_bench.report.protocol_notes import protocol_note, protocol_warnings
    from vlm_bench.report.tables import summary_rich
    from vlm_bench.report.text import frame_rich

    by = list(result.options.by)
    for g in result.groupings:
        title = "Our four suites" if g.name == "suites" else "The paper's three columns"
        target.print(summary_rich(result.tables[g.name], by, title, target.width, g))
    target.print(protocol_note(result.frame), highlight=False)
    for warning in protocol_warnings(result.frame, by):
        target.print(f"[yellow]Warning. {warning}[/]", highlight=False)
    for section in result.sections:
        table = frame_rich(section.frame, section.title, section.caption, section.numeric)
        if section.narrow is not None and _width(target, table) > target.width:
            numeric = ("value [CI]",)
            table = frame_rich(section.narrow, section.title, section.caption, numeric)
        target.print(table)


def _width(console: Console, table: object) -> int:
    from rich.measure import Measurement

    options = console.options.update(max_width=10_000)
    return Measurement.get(console, options, table).maximum  # type: ignore[arg-type]


def register(app: typer.Typer) -> None:
    """Add ``report`` to ``app``."""
    app.command()(report)
