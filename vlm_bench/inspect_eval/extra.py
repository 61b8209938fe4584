"""The ``inspect`` extra: checked before anything imports ``inspect_ai``."""

from __future__ import annotations

import importlib.util

from vlm_bench.errors import MissingExtraError


def require_inspect() -> None:
    """Refuse to go on without inspect_ai.

    Raises:
        MissingExtraError: ``pip install 'vlm-bench[inspect]'``.
    """
    if importlib.util.find_spec("inspect_ai") is None:
        raise MissingExtraError("inspect_ai", "inspect")
