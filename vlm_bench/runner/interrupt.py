"""Ctrl-C or SIGTERM during a run: stop at the next episode boundary, never inside native code.

A ``KeyboardInterrupt`` raised by Python's default handler can surface inside a C++ binding
(MuJoCo's pybind11 argument conversion turns it into a ``TypeError``), so the first Ctrl-C
(SIGINT) or SIGTERM only sets a flag that the pipeline checks between batches, between executions
and while it waits for one; a second one interrupts at once. SIGTERM (what ``kill``, schedulers
and container runtimes send) stops a run as Ctrl-C does, raising :class:`Terminated`.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from types import FrameType


class Terminated(KeyboardInterrupt):
    """The run was stopped by SIGTERM (a ``KeyboardInterrupt``, so it unwinds the same way)."""


class StopFlag:
    """Set by the first SIGINT or SIGTERM; the pipeline raises when it sees it."""

    def __init__(self) -> None:
        self.requested = False
        self.terminated = False
        """The stop came from SIGTERM."""

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` (:class:`Terminated` for SIGTERM) if a stop was
        requested."""
        if self.requested:
            raise Terminated if self.terminated else KeyboardInterrupt


@contextmanager
def _deferred(signum: signal.Signals, flag: StopFlag) -> Iterator[None]:
    """Route ``signum`` to ``flag`` (kept ignored where it is ignored)."""
    previous = signal.getsignal(signum)
    if previous is signal.SIG_IGN:  # e.g. SIGINT of a background job: keep ignoring
        yield
        return

    def handle(received: int, frame: FrameType | None) -> None:
        if flag.requested:  # a second signal: the user insists
            raise Terminated if flag.terminated else KeyboardInterrupt
        flag.requested = True
        flag.terminated = received == signal.SIGTERM

    signal.signal(signum, handle)
    try:
        yield
    finally:
        signal.signal(signum, previous)


@contextmanager
def deferred_interrupt() -> Iterator[StopFlag]:
    """Defer the first SIGINT or SIGTERM to the returned flag (only in the main thread; else
    a no-op)."""
    flag = StopFlag()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    with ExitStack() as stack:
        stack.enter_context(_deferred(signal.SIGINT, flag))
        stack.enter_context(_deferred(signal.SIGTERM, flag))
        yield flag
