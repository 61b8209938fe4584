"""Worker processes die with the process that started them.

An execution worker whose run was killed (SIGKILL, an out-of-memory kill, a crash) must not live on
under PID 1 holding its memory. On Linux the kernel sends the worker SIGKILL when its parent
exits (``prctl(PR_SET_PDEATHSIG)``); elsewhere a daemon thread of the worker checks every
:data:`POLL_S` seconds that its parent is still the process that started it, and exits when it
is not.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time

POLL_S = 1.0
"""How often the fallback watch looks at the parent (s)."""
_PR_SET_PDEATHSIG = 1


def _kernel_kills_on_parent_death() -> bool:
    """Ask Linux to SIGKILL this process when its parent exits; False where it cannot."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _watch(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(POLL_S)
    os._exit(1)  # orphaned: the run is gone, nothing to hand results to


def die_with_parent(parent: int) -> None:
    """Make this process exit when ``parent`` (the pid that started it) exits.

    Call it first thing in a worker (a pool initializer). A parent that died before the call
    is seen at once.
    """
    if not _kernel_kills_on_parent_death():
        threading.Thread(target=_watch, args=(parent,), name="parent-watch", daemon=True).start()
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)
