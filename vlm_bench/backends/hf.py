"""Any Hugging Face image-text-to-text model: ``AutoProcessor`` + ``AutoModelForImageTextToText``.

Prompts go through the processor's own chat template (image parts in order, then text), in
left-padded batches; bf16 with ``device_map="auto"`` on CUDA, float32 on CPU; greedy unless a
temperature is set. Decoding follows the run's :class:`GenerationConfig` alone: the checkpoint's
``generation_config`` (Qwen2.5-VL ships ``repetition_penalty`` 1.05, others ``top_k``/``top_p``)
is replaced at load by one that keeps only its special tokens, so hf decodes as vllm does.
torch and transformers are imported only when the backend is built.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from typing import Any, Literal

from pydantic import Field

from vlm_bench.backends.backend import (
    OPERATIONAL,
    Backend,
    BackendArgs,
    require_schemas,
    share_wall_time,
)
from vlm_bench.backends.hf_constrained import SchemaConstraint
from vlm_bench.backends.hf_decoding import hf_generate_kwargs, neutral_generation_config
from vlm_bench.backends.image_limits import ImageLimits, apply_image_limits
from vlm_bench.errors import ConfigError, MissingExtraError
from vlm_bench.types.generation import (
    GenerationConfig,
    GenerationRequest,
    GenerationResult,
    ImagePart,
)


class HfArgs(BackendArgs):
    """``-M`` arguments of the hf backend."""

    dtype: Literal["auto", "bfloat16", "float16", "float32"] = Field(
        default="auto", description="Weights dtype; auto = bfloat16 on CUDA, float32 on CPU."
    )
    device_map: str = Field(
        default="auto",
        description="device_map on CUDA (ignored on CPU).",
        json_schema_extra=OPERATIONAL,
    )
    trust_remote_code: bool = Field(default=False, description="Run the model repo's own code.")
    attn_implementation: str | None = Field(
        default=None, description="Attention kernel, e.g. sdpa, flash_attention_2."
    )
    revision: str | None = Field(default=None, description="Hub revision (branch, tag, commit).")
    system_role: bool = Field(default=True, description="Send a system message (else merge).")
    min_pixels: int | None = Field(
        default=None, gt=0, description="Fewest pixels per image (Qwen2/2.5/3-VL, GLM-4.1V)."
    )
    max_pixels: int | None = Field(
        default=None, gt=0, description="Most pixels per image (Qwen2/2.5/3-VL, GLM-4.1V)."
    )
    max_tiles: int | None = Field(
        default=None, gt=0, description="Most tiles per image (InternVL)."
    )

    def image_limits(self) -> ImageLimits:
        """The pixel and tile limits given."""
        return ImageLimits(
            min_pixels=self.min_pixels, max_pixels=self.max_pixels, max_tiles=self.max_tiles
        )


_log = logging.getLogger(__name__)


def hf_messages(
    request: GenerationRequest, images: Sequence[Any], *, system_role: bool = True
) -> list[dict[str, Any]]:
    """Chat messages for a processor's chat template: ``{"type": "image"}`` parts in order,
    earlier turns (a closed loop's rounds) between the system message and the user turn.

    ``images`` are the decoded request images (PIL, :meth:`GenerationRequest.images` order),
    attached to their parts so templates that read them (or processors that load from
    messages) see the same order.
    """
    it = iter(images)
    turns = [(t.role, t.content) for t in request.history] + [("user", request.user)]
    messages: list[dict[str, Any]] = []
    if request.system and system_role:
        messages.append({"role": "system", "content": [{"type": "text", "text": request.system}]})
    for i, (role, parts) in enumerate(turns):
        content: list[dict[str, Any]] = []
        if i == 0 and request.system and not system_role:
            content.append({"type": "text", "text": request.system})
        for part in parts:
            if isinstance(part, ImagePart):
                content.append({"type": "image", "image": next(it)})
            else:
                content.append({"type": "text", "text": part.text})
        messages.append({"role": role, "content": content})
    return messages


def _decode_png(png: bytes) -> Any:
    import io

    from PIL import Image

    return Image.open(io.BytesIO(png)).convert("RGB")


def _eos_ids(model: Any, tokenizer: Any) -> list[int]:
    eos = model.generation_config.eos_token_id
    if eos is None:
        eos = tokenizer.eos_token_id
    return [eos] if isinstance(eos, int) else list(eos or [])


class HfBackend(Backend):
    """Local transformers inference, batched."""

    name = "hf"
    Args = HfArgs

    def __init__(self, model: str, args: HfArgs | None = None) -> None:
        try:
            import torch
            import transformers as _transformers
        except ImportError:
            raise MissingExtraError("torch and transformers", "hf") from None
        self.model_id = model
        self.args = args or HfArgs()
        self._torch = torch
        transformers: Any = _transformers  # untyped in places; used through Any on purpose
        cuda = torch.cuda.is_available()
        dtype = (
            self.args.dtype if self.args.dtype != "auto" else ("bfloat16" if cuda else "float32")
        )
        common: dict[str, Any] = {"trust_remote_code": self.args.trust_remote_code}
        if self.args.revision:
            common["revision"] = self.args.revision
        processor = transformers.AutoProcessor.from_pretrained(model, **common)
        self._limit_images(processor, model)  # before the weights load: a bad limit fails fast
        major, minor = (int(x) for x in transformers.__version__.split(".")[:2])
        dtype_key = "dtype" if (major, minor) >= (4, 56) else "torch_dtype"
        load: dict[str, Any] = {**common, dtype_key: getattr(torch, dtype)}
        if cuda:
            load["device_map"] = self.args.device_map
        if self.args.attn_implementation:
            load["attn_implementation"] = self.args.attn_implementation
        loaded = transformers.AutoModelForImageTextToText.from_pretrained(model, **load)
        self._adopt(processor, loaded.eval(), transformers)

    @classmethod
    def from_loaded(
        cls, model_id: str, processor: Any, model: Any, args: HfArgs | None = None
    ) -> HfBackend:
        """A backend around a processor and model already in memory (same setup as a load).

        Raises:
            ConfigError: A pixel/tile limit the processor has no setting for.
        """
        import torch
        import transformers

        backend = cls.__new__(cls)
        backend.model_id, backend.args, backend._torch = model_id, args or HfArgs(), torch
        backend._limit_images(processor, model_id)
        backend._adopt(processor, model.eval(), transformers)
        return backend

    def _adopt(self, processor: Any, model: Any, transformers: Any) -> None:
        """Take a loaded processor and model: left padding, and the run's decoding only."""
        self.processor = processor
        self.tokenizer = getattr(processor, "tokenizer", processor)
        self.tokenizer.padding_side = "left"  # generation continues at the right edge
        self.model = model
        neutral, dropped = neutral_generation_config(transformers, model.generation_config)
        self.model.generation_config = neutral
        self.checkpoint_generation = dropped  # what decoding does not take from the checkpoint
        if dropped:
            _log.warning(
                "hf: %s: the checkpoint's generation_config (%s) is not used; decoding follows "
                "the run's settings (see the manifest's config.generation)",
                self.model_id,
                ", ".join(f"{k}={v!r}" for k, v in sorted(dropped.items())),
            )
        self._constraint: SchemaConstraint | None = None

    def _limit_images(self, processor: Any, model: str) -> None:
        limits = self.args.image_limits()
        image_processor = getattr(processor, "image_processor", None)
        if image_processor is None:
            given = limits.given()
            if given:
                raise ConfigError(f"-M {sorted(given)[0]}: {model} has no image processor")
            self.image_settings: dict[str, int] = {}
            return
        self.image_settings = apply_image_limits(image_processor, limits, model)

    def _encode(self, batch: Sequence[GenerationRequest]) -> Any:
        texts: list[str] = []
        images: list[list[Any]] = []
        for req in batch:
            pil = [_decode_png(p.png) for p in req.images()]
            messages = hf_messages(req, pil, system_role=self.args.system_role)
            texts.append(
                self.processor.apply_chat_template(
                    messages, add_generation_prompt=True, tokenize=False
                )
            )
            images.append(pil)
        kwargs: dict[str, Any] = {"text": texts, "padding": True, "return_tensors": "pt"}
        if any(images):
            kwargs["images"] = images
        inputs = self.processor(**kwargs)
        device, dtype = self.model.device, self.model.dtype
        return {
            k: (v.to(device, dtype) if v.is_floating_point() else v.to(device))
            for k, v in inputs.items()
            if hasattr(v, "to")
        }

    def _gen_kwargs(
        self, batch: Sequence[GenerationRequest], config: GenerationConfig, eos: list[int]
    ) -> dict[str, Any]:
        kwargs = hf_generate_kwargs(config)
        if not config.greedy:
            self._torch.manual_seed(config.seed)
        pad = self.tokenizer.pad_token_id
        kwargs["pad_token_id"] = pad if pad is not None else (eos[0] if eos else None)
        if config.constrained:
            if self._constraint is None:
                vocab = self.model.get_output_embeddings().weight.shape[0]
                self._constraint = SchemaConstraint(self.tokenizer, vocab, eos)
            kwargs["logits_processor"] = [self._constraint.logits_processor(batch)]
        return kwargs

    def _run(
        self, batch: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        start = time.perf_counter()
        eos = _eos_ids(self.model, self.tokenizer)
        inputs = self._encode(batch)
        with self._torch.inference_mode():
            out = self.model.generate(**inputs, **self._gen_kwargs(batch, config, eos))
        prompt_len = inputs["input_ids"].shape[1]
        results: list[GenerationResult] = []
        for i, req in enumerate(batch):
            new = out[i, prompt_len:].tolist()
            stop = next((j for j, tok in enumerate(new) if tok in eos), None)
            kept = new if stop is None else new[: stop + 1]
            results.append(
                GenerationResult(
                    id=req.id,
                    text=self.tokenizer.decode(kept, skip_special_tokens=True),
                    prompt_tokens=int(inputs["attention_mask"][i].sum()),
                    completion_tokens=len(kept),
                    finish_reason="stop" if stop is not None else "length",
                )
            )
        return share_wall_time(results, time.perf_counter() - start)

    def _run_splitting(
        self, batch: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Run a batch; on out-of-memory halve it, and record the error for a lone request."""
        try:
            return self._run(batch, config)
        except self._torch.OutOfMemoryError as exc:
            if self._torch.cuda.is_available():
                self._torch.cuda.empty_cache()
            if len(batch) == 1:
                return [GenerationResult(id=batch[0].id, error=f"OutOfMemoryError: {exc}"[:500])]
        half = len(batch) // 2
        return self._run_splitting(batch[:half], config) + self._run_splitting(batch[half:], config)

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Generate in batches of ``config.batch_size``; results in request order."""
        require_schemas(self.name, requests, config)
        results: list[GenerationResult] = []
        for lo in range(0, len(requests), config.batch_size):
            results.extend(self._run_splitting(requests[lo : lo + config.batch_size], config))
        return results

    def close(self) -> None:
        """Drop the model and free GPU memory."""
        if getattr(self, "model", None) is not None:
            self.model = None
            if self._torch.cuda.is_available():
                self._torch.cuda.empty_cache()
