"""vlm-bench: evaluate vision-language models as planners for aerial manipulation.

The public API (``vlm_bench.run``, ``vlm_bench.rescore``, ...) is loaded lazily so that importing
the package stays light (no torch, mujoco or pandas).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from vlm_bench.api import (
        RunConfig,
        RunResult,
        load_run,
        replay,
        rescore,
        run,
        run_dir_for,
        score_output,
    )

__version__ = "0.1.0"
__all__ = [
    "RunConfig",
    "RunResult",
    "load_run",
    "replay",
    "rescore",
    "run",
    "run_dir_for",
    "score_output",
]
_API = frozenset(__all__)


def __getattr__(name: str) -> Any:
    """Lazy access to the public API without importing it at package import."""
    if name in _API:
        from vlm_bench import api

        return getattr(api, name)
    raise AttributeError(f"module 'vlm_bench' has no attribute {name!r}")
