"""Native libraries that must be loaded before the process's first OpenGL (EGL) context.

Triton's ``libtriton`` (imported by torch's compiler stack as transformers loads a model, and by
vllm and xgrammar) kills the process with SIGSEGV when it is first loaded after MuJoCo created an
EGL context; loaded before it, both work. A process that will render and then load a model calls
:func:`preload_before_gl` before it renders.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

BEFORE_GL = ("triton._C.libtriton",)
"""Modules that crash when first imported after an EGL context exists (when installed)."""


def preload_before_gl() -> tuple[str, ...]:
    """Import every installed module of :data:`BEFORE_GL` not yet imported.

    Returns:
        The modules imported by this call. One that fails to import is skipped: the backend
        that needs it reports the broken install when it loads.
    """
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
