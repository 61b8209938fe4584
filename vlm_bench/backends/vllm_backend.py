"""Offline vLLM engine (``vllm.LLM``) with tensor parallelism; optional extra.

Messages are the OpenAI chat format with data-URL images (as for the ``openai`` backend), fed
to ``LLM.chat`` in one call per batch; vLLM schedules the batch itself.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from pydantic import Field

from vlm_bench.backends.base import Backend, BackendArgs, require_schemas
from vlm_bench.backends.messages import openai_messages
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult


class VllmArgs(BackendArgs):
    """``-M`` arguments of the vllm backend."""

    tensor_parallel_size: int = Field(default=1, ge=1, description="GPUs to shard across.")
    gpu_memory_utilization: float = Field(default=0.9, gt=0, le=1, description="GPU memory share.")
    max_model_len: int | None = Field(default=None, gt=0, description="Context length cap.")
    max_images: int = Field(default=4, ge=0, description="Images per prompt the engine admits.")
    dtype: str = Field(default="auto", description="Weights dtype.")
    trust_remote_code: bool = Field(default=False, description="Run the model repo's own code.")
    enforce_eager: bool = Field(default=False, description="Disable CUDA graphs.")
    system_role: bool = Field(default=True, description="Send a system message (else merge).")


def sampling_kwargs(config: GenerationConfig) -> dict[str, Any]:
    """``SamplingParams`` keyword arguments (the schema is added per request)."""
    kwargs: dict[str, Any] = {
        "max_tokens": config.max_new_tokens,
        "temperature": config.temperature,
        "top_p": config.top_p,
    }
    if not config.greedy:
        kwargs["seed"] = config.seed
    return kwargs


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
        engine: dict[str, Any] = {
            "model": model,
            "tensor_parallel_size": self.args.tensor_parallel_size,
            "gpu_memory_utilization": self.args.gpu_memory_utilization,
            "dtype": self.args.dtype,
            "trust_remote_code": self.args.trust_remote_code,
            "enforce_eager": self.args.enforce_eager,
            "limit_mm_per_prompt": {"image": self.args.max_images},
        }
        if self.args.max_model_len is not None:
            engine["max_model_len"] = self.args.max_model_len
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
            latency = time.perf_counter() - start
            for req, out in zip(batch, outputs, strict=True):
                completion = out.outputs[0]
                results.append(
                    GenerationResult(
                        id=req.id,
                        text=completion.text,
                        latency_s=latency,
                        prompt_tokens=len(out.prompt_token_ids or []),
                        completion_tokens=len(completion.token_ids),
                        finish_reason=completion.finish_reason,
                    )
                )
        return results
