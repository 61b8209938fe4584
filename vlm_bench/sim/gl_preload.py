"""Native libraries that must be loaded before the process's first OpenGL (EGL) context.

Triton's ``libtriton`` (imported by torch's compiler stack as transformers loads a model, and by
vllm and xgrammar) kills the process with SIGSEGV when it is first loaded after MuJoCo created an
EGL context; loaded before it, both work. The renderer calls
:func:`before_first_gl_context` before it makes a process's first GL context, so whatever a
process does first (a run, a rescore, a gym environment, a video), the library is in memory
before EGL; :func:`preload_before_gl` never imports it once a context exists (that import is
the crash).
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

BEFORE_GL = ("triton._C.libtriton",)
"""Modules that crash when first imported after an EGL context exists (when installed)."""
_gl_started = False
"""Whether this process has made a GL context (through :func:`before_first_gl_context`)."""


def before_first_gl_context() -> None:
    """Preload :data:`BEFORE_GL`, then note that GL is in use (the renderer calls this before
    it makes a GL context)."""
    global _gl_started
    if not _gl_started:
        preload_before_gl()
        _gl_started = True


def preload_before_gl() -> tuple[str, ...]:
    """Import every installed module of :data:`BEFORE_GL` not yet imported.

    Returns:
        The modules imported by this call: none once this process has made a GL context. One
        that fails to import is skipped: the backend that needs it reports the broken install
        when it loads.
    """
    if _gl_started:
        return ()
    loaded: list[str] = []
    for name in BEFORE_GL:
        if name in sys.modules or importlib.util.find_spec(name.partition(".")[0]) is None:
            continue
        try:
            importlib.import_module(name)
        except (ImportError, OSError):
            continue
        loaded.append(name)
    return tuple(loaded)
