"""Offline vLLM engine (``vllm.LLM``) with tensor parallelism; optional extra.

Messages are the OpenAI chat format with data-URL images (as for the ``openai`` backend), fed
to ``LLM.chat`` in one call per batch; vLLM schedules the batch itself. Sampling takes every
setting of :meth:`GenerationConfig.decoding`, the same the hf backend passes to ``generate``.
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from typing import Any

from pydantic import Field, field_validator

from vlm_bench.backends.backend import Backend, BackendArgs, require_schemas, share_wall_time
from vlm_bench.backends.image_limits import ImageLimits
from vlm_bench.backends.messages import openai_messages
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

DEFAULT_MAX_MODEL_LEN = 32768
"""Context cap when none is given: four 448 px views and the prompt fit in every paper model
(LLaVA-OneVision's anyres tiles take the most), and the KV cache is not sized for the 128k-256k
contexts the checkpoints declare."""

PIXEL_BUDGET_TYPES = frozenset({"qwen2_vl", "qwen2_5_vl", "qwen3_vl", "qwen3_vl_moe"})
"""Model types whose vLLM processor takes ``min_pixels``/``max_pixels`` (vLLM's docs)."""
TILE_TYPES = {"internvl_chat": "max_dynamic_patch"}
"""Model types whose vLLM processor takes a tile count, and the keyword it has."""


class VllmArgs(BackendArgs):
    """``-M`` arguments of the vllm backend."""

    tensor_parallel_size: int = Field(default=1, ge=1, description="GPUs to shard across.")
    gpu_memory_utilization: float = Field(default=0.9, gt=0, le=1, description="GPU memory share.")
    max_model_len: int = Field(
        default=DEFAULT_MAX_MODEL_LEN, gt=0, description="Context length cap (tokens)."
    )
    max_images: int = Field(default=4, ge=0, description="Images per prompt the engine admits.")
    dtype: str = Field(default="auto", description="Weights dtype.")
    trust_remote_code: bool = Field(default=False, description="Run the model repo's own code.")
    enforce_eager: bool = Field(default=False, description="Disable CUDA graphs.")
    system_role: bool = Field(default=True, description="Send a system message (else merge).")
    mm_processor_kwargs: dict[str, Any] | None = Field(
        default=None, description='Processor arguments as JSON, e.g. {"max_pixels": 1000000}.'
    )
    hf_overrides: dict[str, Any] | None = Field(
        default=None, description='Config overrides as JSON, e.g. {"architectures": [...]}.'
    )
    min_pixels: int | None = Field(default=None, gt=0, description="Fewest pixels per image.")
    max_pixels: int | None = Field(default=None, gt=0, description="Most pixels per image.")
    max_tiles: int | None = Field(default=None, gt=0, description="Most tiles per image.")

    @field_validator("mm_processor_kwargs", "hf_overrides", mode="before")
    @classmethod
    def _json_object(cls, value: Any) -> Any:
        if isinstance(value, str):
            try:
                value = json.loads(value)
            except json.JSONDecodeError as exc:
                raise ValueError(f"not JSON: {exc.msg}") from None
            if not isinstance(value, dict):
                raise ValueError("must be a JSON object")
        return value


def sampling_kwargs(config: GenerationConfig) -> dict[str, Any]:
    """``SamplingParams`` keyword arguments (the schema is added per request): every setting of
    :meth:`GenerationConfig.decoding`, greedy as temperature 0 with no top-p/top-k limit."""
    decoding = config.decoding()
    top_k = int(decoding.get("top_k", 0))
    kwargs: dict[str, Any] = {
        "max_tokens": decoding["max_new_tokens"],
        "repetition_penalty": decoding["repetition_penalty"],
        "temperature": decoding.get("temperature", 0.0),
        "top_p": decoding.get("top_p", 1.0),
        "top_k": top_k if top_k > 0 else -1,  # -1 = no limit in every vLLM release
    }
    if "seed" in decoding:
        kwargs["seed"] = decoding["seed"]
    return kwargs


def model_type(model: str, revision: str | None = None) -> str:
    """``model_type`` of a checkpoint's config.json (hub id or folder), without its code."""
    from transformers import PretrainedConfig

    try:
        config, _ = PretrainedConfig.get_config_dict(model, revision=revision)
    except OSError as exc:
        raise ConfigError(f"cannot read the config of {model}: {exc}") from None
    return str(config.get("model_type", ""))


def processor_kwargs(args: VllmArgs, kind: str) -> dict[str, Any]:
    """``mm_processor_kwargs``: the given JSON plus the pixel/tile limits in the keywords the
    model type's vLLM processor takes.

    Raises:
        ConfigError: A limit for a model type whose keyword vlm-bench does not know.
    """
    out = dict(args.mm_processor_kwargs or {})
    limits = ImageLimits(
        min_pixels=args.min_pixels, max_pixels=args.max_pixels, max_tiles=args.max_tiles
    ).given()
    if not limits:
        return out
    if kind in PIXEL_BUDGET_TYPES and "max_tiles" not in limits:
        return {**out, **limits}
    if kind in TILE_TYPES and set(limits) == {"max_tiles"}:
        return {**out, TILE_TYPES[kind]: limits["max_tiles"]}
    first = sorted(limits)[0]
    raise ConfigError(
        f"-M {first}: no such limit for model type {kind!r} in the vllm backend (pixels: "
        f"{', '.join(sorted(PIXEL_BUDGET_TYPES))}; tiles: {', '.join(TILE_TYPES)}); pass the "
        "model's own keyword with -M mm_processor_kwargs='{...}'"
    )


class VllmBackend(Backend):
    """Batched offline generation with vLLM."""

    name = "vllm"
    Args = VllmArgs

    def __init__(self, model: str, args: VllmArgs | None = None) -> None:
        if not model:
            raise ConfigError("backend 'vllm' needs a model: --model vllm/<hf id or path>")
        try:
            import vllm
        except ImportError:
            raise MissingExtraError("vllm", "vllm") from None
        self.model_id = model
        self.args = args or VllmArgs()
        self._vllm = vllm
        limits_given = any(
            v is not None for v in (self.args.min_pixels, self.args.max_pixels, self.args.max_tiles)
        )
        mm_kwargs = processor_kwargs(self.args, model_type(model) if limits_given else "")
        engine: dict[str, Any] = {
            "model": model,
            "tensor_parallel_size": self.args.tensor_parallel_size,
            "gpu_memory_utilization": self.args.gpu_memory_utilization,
            "max_model_len": self.args.max_model_len,
            "dtype": self.args.dtype,
            "trust_remote_code": self.args.trust_remote_code,
            "enforce_eager": self.args.enforce_eager,
            "limit_mm_per_prompt": {"image": self.args.max_images},
        }
        if mm_kwargs:
            engine["mm_processor_kwargs"] = mm_kwargs
        if self.args.hf_overrides:
            engine["hf_overrides"] = self.args.hf_overrides
        self.engine_args = engine
        self.llm = vllm.LLM(**engine)

    def _sampling_params(self, request: GenerationRequest, config: GenerationConfig) -> Any:
        kwargs = sampling_kwargs(config)
        if config.constrained and request.json_schema is not None:
            # vLLM >= 0.10 names it structured_outputs; older releases guided_decoding.
            params_mod = self._vllm.sampling_params
            if hasattr(params_mod, "StructuredOutputsParams"):
                kwargs["structured_outputs"] = params_mod.StructuredOutputsParams(
                    json=request.json_schema
                )
            else:
                kwargs["guided_decoding"] = params_mod.GuidedDecodingParams(
                    json=request.json_schema
                )
        return self._vllm.SamplingParams(**kwargs)

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """One ``LLM.chat`` call per batch of ``config.batch_size`` requests."""
        require_schemas(self.name, requests, config)
        results: list[GenerationResult] = []
        for lo in range(0, len(requests), config.batch_size):
            batch = requests[lo : lo + config.batch_size]
            start = time.perf_counter()
            outputs = self.llm.chat(
                [openai_messages(r, system_role=self.args.system_role) for r in batch],
                sampling_params=[self._sampling_params(r, config) for r in batch],
                use_tqdm=False,
            )
            answers: list[GenerationResult] = []
            for req, out in zip(batch, outputs, strict=True):
                completion = out.outputs[0]
                answers.append(
                    GenerationResult(
                        id=req.id,
                        text=completion.text,
                        prompt_tokens=len(out.prompt_token_ids or []),
                        completion_tokens=len(completion.token_ids),
                        finish_reason=completion.finish_reason,
                    )
                )
            results.extend(share_wall_time(answers, time.perf_counter() - start))
        return results
