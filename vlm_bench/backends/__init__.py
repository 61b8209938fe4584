"""Model backends: one required method, ``generate(requests, config) -> results``.

Importing this package imports no heavy dependency (torch, transformers, openai, vllm); each
backend imports its own when it is built.
"""

from vlm_bench.backends.backend import Backend, BackendArgs, parse_args
from vlm_bench.backends.backend_registry import (
    BACKENDS,
    load_plugins,
    operational_args,
    parse_model_args,
    resolve_backend,
    split_model,
)

__all__ = [
    "BACKENDS",
    "Backend",
    "BackendArgs",
    "load_plugins",
    "operational_args",
    "parse_args",
    "parse_model_args",
    "resolve_backend",
    "split_model",
]
