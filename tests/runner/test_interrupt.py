"""First Ctrl-C defers to the episode boundary; a second one interrupts at once."""

from __future__ import annotations

import os
import signal

import pytest

from vlm_bench.runner.interrupt import Terminated, deferred_interrupt


@pytest.fixture
def python_sigint_handler():  # type: ignore[no-untyped-def]
    # xdist workers ignore SIGINT; give this test Python's own handler, as in a terminal.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_first_sigint_sets_the_flag_second_raises(python_sigint_handler: None) -> None:
    with deferred_interrupt() as stop:
        stop.check()  # nothing requested yet
        os.kill(os.getpid(), signal.SIGINT)
        assert stop.requested
        with pytest.raises(KeyboardInterrupt):
            stop.check()
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_ignored_sigint_stays_ignored() -> None:
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with deferred_interrupt() as stop:
            os.kill(os.getpid(), signal.SIGINT)
            assert not stop.requested
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_sigterm_stops_like_ctrl_c_and_says_so() -> None:
    previous = signal.getsignal(signal.SIGTERM)
    with deferred_interrupt() as stop:
        os.kill(os.getpid(), signal.SIGTERM)
        assert stop.requested and stop.terminated
        with pytest.raises(Terminated):
            stop.check()
        with pytest.raises(Terminated):
            os.kill(os.getpid(), signal.SIGTERM)  # a second one: at once
    assert signal.getsignal(signal.SIGTERM) is previous
    assert issubclass(Terminated, KeyboardInterrupt)  # unwinds as Ctrl-C does
