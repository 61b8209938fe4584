"""What ``run`` and ``rescore`` print after a run: the summary table and what went wrong."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.console import Console

from vlm_bench.cli.options import table_console

if TYPE_CHECKING:
    from vlm_bench.api import RunResult

console = Console()


def print_run_summary(result: RunResult) -> None:
    """Print a run's table, where its files are, and what has no result."""
    from vlm_bench.cli.protocol_option import protocol_line
    from vlm_bench.report import summary_rich
    from vlm_bench.types.execution import FailureCode
    from vlm_bench.types.protocol_match import manifest_protocol

    # Piped: no terminal width to respect, so the table is not wrapped or cut.
    shown = table_console(console)
    shown.print(summary_rich(result.summary, title=result.run_id, width=shown.width))
    stats = result.stats
    line = f"{result.run_dir}: summary.md, summary.csv, records.jsonl ({stats.total} episodes"
    if stats.skipped:
        line += f", {stats.skipped} resumed"
    if stats.cached:
        line += f", {stats.cached} from the response cache"
    if stats.executed:
        line += f", {stats.executed} plan(s) executed"
    console.print(line + ")", highlight=False, soft_wrap=True)
    console.print(protocol_line(manifest_protocol(result.manifest)), highlight=False)
    unanswered = [r for r in result.records if not r.ok]
    if unanswered:
        first = unanswered[0]
        console.print(
            f"[yellow]{len(unanswered)} of {len(result.records)} episode(s) have no result "
            f"(the backend failed after its retries, or an execution was lost; e.g. {first.key}: "
            f"{first.backend_error}); re-run the same command to retry them[/]",
            soft_wrap=True,
            highlight=False,
        )
    crashed = [
        (r.key, r.execution.failure_reason)
        for r in result.records
        if r.execution is not None and r.execution.failure_code is FailureCode.EXECUTOR_CRASH
    ]
    if crashed:
        key, reason = crashed[0]
        console.print(
            f"[yellow]{len(crashed)} execution(s) raised in the executor (recorded as "
            f"failures), e.g. {key}: {reason}[/]",
            soft_wrap=True,
            highlight=False,
        )
