"""Progress on stderr (rich bars on a terminal, plain lines elsewhere), or nothing when
disabled: a bar for long work (:func:`progress_bar`) and a run's (:class:`RunProgress`)."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)


@contextmanager
def progress_bar(
    total: int, label: str, *, enabled: bool = True
) -> Iterator[Callable[[int], None]]:
    """Yield ``advance(n)``; shows ``label``, a bar, done/total, elapsed and remaining time."""
    if not enabled:
        yield lambda n: None
        return
    columns = (
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("eta"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=Console(stderr=True), transient=False) as bar:
        task = bar.add_task(label, total=total)

        def advance(n: int) -> None:
            if n:
                bar.advance(task, n)

        yield advance


def _clock(seconds: float) -> str:
    seconds = max(0, round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class RunProgress:
    """Progress of a run: episodes written (with an ETA), answers generated, and executions done /
    running / queued. On a terminal: rich bars on stderr; elsewhere (a log file, CI): one line
    every ``every`` episodes written, and one at the end.

    Args:
        total: Episodes of the run.
        label: Shown first (the run id).
        enabled: False = show nothing.
        every: Episodes between plain lines.
        console: Where to write (default: stderr).
    """

    def __init__(
        self,
        total: int,
        label: str = "",
        *,
        enabled: bool = True,
        every: int = 10,
        console: Console | None = None,
    ) -> None:
        self.total = total
        self.label = label
        self.enabled = enabled
        self.every = max(1, every)
        self.console = console or Console(stderr=True)
        self.done = 0
        """Episodes written (or already done when the run resumed)."""
        self.generated_n = 0
        """Episodes answered (or already done)."""
        self.executions = (0, 0, 0, 0)
        """Executions: (submitted, finished, running, queued)."""
        self._start = time.monotonic()
        self._start_done = 0
        self._last_line = 0
        self._bar: Progress | None = None

    def __enter__(self) -> RunProgress:
        if self.enabled and self.console.is_terminal:
            columns = (
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[note]}"),
                TimeElapsedColumn(),
                TextColumn("eta"),
                TimeRemainingColumn(),
            )
            self._bar = Progress(*columns, console=self.console, transient=False)
            self._bar.start()
            self._rows = {
                name: self._bar.add_task(name, total=self.total, note="")
                for name in (f"{self.label} episodes", "  generated", "  executions")
            }
        return self

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._refresh()
            self._bar.stop()
        elif self.enabled and self.done != self._last_line:
            self.console.print(self.line(), highlight=False, soft_wrap=True)

    # ---- events ---------------------------------------------------------------------------
    def skipped(self, n: int) -> None:
        """``n`` episodes were done before this run started (resume)."""
        self.done += n
        self.generated_n += n
        self._start_done = self._last_line = self.done
        self._update()

    def generated(self, n: int) -> None:
        """``n`` answers were scored."""
        self.generated_n += n
        self._update()

    def written(self, n: int) -> None:
        """``n`` records were written."""
        self.done += n
        self._update()
        if self._bar is None and self.enabled and self.done - self._last_line >= self.every:
            self._last_line = self.done
            self.console.print(self.line(), highlight=False, soft_wrap=True)

    def executions_changed(self, submitted: int, finished: int, running: int, queued: int) -> None:
        """The execution pool's counts changed."""
        self.executions = (submitted, finished, running, queued)
        self._update()

    # ---- display --------------------------------------------------------------------------
    def eta_s(self) -> float | None:
        """Seconds left at the rate episodes were written so far (None before the first)."""
        written = self.done - self._start_done
        if written <= 0:
            return None
        rate = written / max(1e-9, time.monotonic() - self._start)
        return (self.total - self.done) / rate

    def line(self) -> str:
        """The plain progress line."""
        submitted, finished, running, queued = self.executions
        eta = self.eta_s()
        parts = [
            f"{self.label} {self.done}/{self.total} episodes".strip(),
            f"generated {self.generated_n}/{self.total}",
            f"executions {finished}/{submitted} done, {running} running, {queued} queued",
            f"elapsed {_clock(time.monotonic() - self._start)}",
            f"eta {_clock(eta) if eta is not None else '?'}",
        ]
        return " | ".join(parts)

    def _update(self) -> None:
        if self._bar is not None:
            self._refresh()

    def _refresh(self) -> None:
        assert self._bar is not None
        submitted, finished, running, queued = self.executions
        episodes, generated, executions = self._rows.values()
        self._bar.update(episodes, completed=self.done)
        self._bar.update(generated, completed=self.generated_n)
        self._bar.update(
            executions,
            completed=finished,
            total=max(submitted, 1),
            note=f"{running} running, {queued} queued",
        )
