"""vlm-bench: evaluate vision-language models as planners for aerial manipulation.

The public API (``vlm_bench.run``, ``vlm_bench.rescore``, ...) is :mod:`vlm_bench.api`, whose
``__all__`` lists it; it is loaded lazily so that importing the package stays light (no torch,
mujoco or pandas).
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from vlm_bench.api import *  # noqa: F403
    from vlm_bench.api import __all__ as __all__
    from vlm_bench.scoring.answer import score_answer as score_answer

__version__ = "0.1.0"

_OUTSIDE_API = {"score_answer": "vlm_bench.scoring.answer"}
"""Public names defined outside :mod:`vlm_bench.api`, by module: importable without the
simulator (``score_answer`` scores a dataset row's answer where MuJoCo is not installed)."""


def __getattr__(name: str) -> Any:
    """Lazy access to the public API (and its ``__all__``) without importing it at package
    import."""
    if name.startswith("__") and name != "__all__":  # __wrapped__, __spec__ …: not the API
        raise AttributeError(f"module 'vlm_bench' has no attribute {name!r}")
    if name in _OUTSIDE_API:
        return getattr(import_module(_OUTSIDE_API[name]), name)
    api = import_module("vlm_bench.api")  # not ``from vlm_bench import``: that calls back here
    if name == "__all__" or name in api.__all__:
        return getattr(api, name)
    raise AttributeError(f"module 'vlm_bench' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_OUTSIDE_API, *import_module("vlm_bench.api").__all__})
