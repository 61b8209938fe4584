"""Ctrl-C during a run: stop at the next episode boundary, never inside native code.

A ``KeyboardInterrupt`` raised by Python's default handler can surface inside a C++ binding
(MuJoCo's pybind11 argument conversion turns it into a ``TypeError``), so the first Ctrl-C only
sets a flag that the pipeline checks between batches; a second Ctrl-C interrupts at once.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType


class StopFlag:
    """Set by the first SIGINT; the pipeline raises ``KeyboardInterrupt`` when it sees it."""

    def __init__(self) -> None:
        self.requested = False

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` if a stop was requested."""
        if self.requested:
            raise KeyboardInterrupt


@contextmanager
def deferred_interrupt() -> Iterator[StopFlag]:
    """Defer the first SIGINT to the returned flag (only in the main thread; else a no-op)."""
    flag = StopFlag()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous is signal.SIG_IGN:  # e.g. a background job: keep ignoring
        yield flag
        return

    def handle(signum: int, frame: FrameType | None) -> None:
        if flag.requested:  # second Ctrl-C: the user insists
            raise KeyboardInterrupt
        flag.requested = True

    signal.signal(signal.SIGINT, handle)
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, previous)
