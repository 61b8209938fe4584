"""The hf backend's decoding settings: the run's :class:`GenerationConfig` and nothing else.

``model.generate`` fills every setting a call leaves unset from ``model.generation_config``,
which a checkpoint ships with its own sampling defaults (Qwen2.5-VL: ``repetition_penalty``
1.05; others ``top_k``, ``top_p``, ``temperature``). The backend swaps it for a neutral one that
keeps only the special tokens, and passes every setting of :meth:`GenerationConfig.decoding`,
the same ones the vllm backend gives ``SamplingParams``.
"""

from __future__ import annotations

from typing import Any

from vlm_bench.types.generation import GenerationConfig

_SPECIAL_TOKENS = ("bos_token_id", "eos_token_id", "pad_token_id", "decoder_start_token_id")
_NOT_DECODING = frozenset(
    {
        "transformers_version",
        "use_cache",
        "output_attentions",
        "output_hidden_states",
        "output_scores",
        "output_logits",
        "return_dict_in_generate",
    }
)
"""Settings that change what generate returns or how fast, never which tokens."""


def hf_generate_kwargs(config: GenerationConfig) -> dict[str, Any]:
    """``model.generate`` keyword arguments for :meth:`GenerationConfig.decoding` (the seed is
    set on torch instead)."""
    decoding = config.decoding()
    kwargs: dict[str, Any] = {
        "max_new_tokens": decoding["max_new_tokens"],
        "repetition_penalty": decoding["repetition_penalty"],
        "do_sample": not config.greedy,
        "num_beams": 1,
    }
    if not config.greedy:
        kwargs.update(
            temperature=decoding["temperature"], top_p=decoding["top_p"], top_k=decoding["top_k"]
        )
    return kwargs


def neutral_generation_config(transformers: Any, checkpoint: Any) -> tuple[Any, dict[str, Any]]:
    """A ``GenerationConfig`` holding only the checkpoint's special tokens, and what it drops.

    ``generate`` fills every setting left unset from ``model.generation_config``; replacing that
    with this one makes the library defaults the only fallback, and the run's settings explicit.
    """
    tokens = {k: getattr(checkpoint, k, None) for k in _SPECIAL_TOKENS}
    neutral = transformers.GenerationConfig(**{k: v for k, v in tokens.items() if v is not None})
    dropped = {
        k: v
        for k, v in checkpoint.to_diff_dict().items()
        if k not in _SPECIAL_TOKENS and k not in _NOT_DECODING and not k.startswith("_")
    }
    return neutral, dropped
