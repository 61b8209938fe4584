"""The exact command lines a model card stands for, derived from its fields.

``run_line(card, "hf")`` and ``run_line(card, "vllm")`` are ``vlm-bench run`` with the card's
checkpoint and ``-M`` arguments; ``serve_line(card)`` starts ``vllm serve`` with the same engine
settings (and ``--generation-config vllm``, so the server adds no checkpoint sampling defaults)
for ``run_line(card, "openai")``.
"""

from __future__ import annotations

import json
import shlex

from vlm_bench.errors import ConfigError
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.model_card import ModelCard

SERVER_URL = "http://127.0.0.1:8000/v1"
"""Where ``vllm serve`` listens by default."""

_FLAGS = {
    "tensor_parallel_size": "--tensor-parallel-size",
    "gpu_memory_utilization": "--gpu-memory-utilization",
    "max_model_len": "--max-model-len",
    "dtype": "--dtype",
    "mm_processor_kwargs": "--mm-processor-kwargs",
    "hf_overrides": "--hf-overrides",
}
_SWITCHES = {"trust_remote_code": "--trust-remote-code", "enforce_eager": "--enforce-eager"}
_CLIENT_ARGS = ("system_role",)
"""vllm arguments that shape the request, not the engine: the openai client takes them."""


def _args(args: dict[str, str]) -> list[str]:
    out: list[str] = []
    for key, value in args.items():
        out += ["-M", f"{key}={value}"]
    return out


def _generation(card: ModelCard) -> list[str]:
    default = GenerationConfig.model_fields["max_new_tokens"].default
    return [] if card.max_new_tokens == default else ["--max-new-tokens", str(card.max_new_tokens)]


def run_line(card: ModelCard, backend: str) -> str:
    """``vlm-bench run`` of the card with ``backend`` (hf, vllm, or openai against
    :func:`serve_line`'s server).

    Raises:
        ConfigError: The card lists the backend as unsupported (the message says why).
    """
    unsupported = {str(k): v for k, v in card.unsupported.items()}
    if backend in unsupported:
        raise ConfigError(f"{card.name} does not run on {backend}: {unsupported[backend]}")
    if backend == "openai":
        client = {k: v for k, v in (card.vllm_args or {}).items() if k in _CLIENT_ARGS}
        words = ["--model", f"openai/{card.hub_id}", *_args({"base_url": SERVER_URL, **client})]
    elif backend in ("hf", "vllm"):
        prefix = "vllm/" if backend == "vllm" else ""
        words = ["--model", prefix + card.hub_id, *_args(card.args_for(backend))]
    else:
        raise ConfigError(f"no recipe for backend {backend!r}; valid: hf, vllm, openai")
    return shlex.join(["vlm-bench", "run", *words, *card.run_options, *_generation(card)])


def serve_line(card: ModelCard) -> str:
    """``vllm serve`` for the openai recipe, with the card's vllm engine settings.

    Raises:
        ConfigError: vLLM cannot serve the card, or its vllm arguments hold a pixel/tile limit,
            which only the vllm backend translates (cards give ``mm_processor_kwargs``).
    """
    if card.vllm_args is None:
        raise ConfigError(f"{card.name} does not run on vllm: {card.unsupported.get('vllm')}")
    words = ["vllm", "serve", card.hub_id]
    images = 4
    for key, value in card.vllm_args.items():
        if key in _FLAGS:
            words += [_FLAGS[key], value]
        elif key in _SWITCHES:
            if value.strip().lower() in ("1", "true", "yes", "on"):
                words.append(_SWITCHES[key])
        elif key == "max_images":
            images = int(value)
        elif key not in _CLIENT_ARGS:
            raise ConfigError(f"{card.name}: vllm argument {key!r} has no vllm serve flag")
    words += ["--limit-mm-per-prompt", json.dumps({"image": images})]
    words += ["--generation-config", "vllm"]
    return shlex.join(words)


def recipe_lines(card: ModelCard) -> dict[str, str]:
    """Every command line of the card by label: hf, vllm, serve + openai (where supported),
    and ``sampled`` (the authors' decoding instead of greedy) where its preset is not greedy."""
    out: dict[str, str] = {}
    for backend in ("hf", "vllm"):
        if backend not in card.unsupported:
            out[backend] = run_line(card, backend)
    if "openai" not in card.unsupported and card.vllm_args is not None:
        out["server"] = serve_line(card)
        out["openai"] = run_line(card, "openai")
    preset = card.sampling
    if preset is not None and (preset.temperature > 0 or preset.repetition_penalty != 1.0):
        out["sampled"] = run_line(card, card.backend) + " --sampling"
    return out
