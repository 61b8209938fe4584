"""Tiny random-weight vision-language models built from config, one per architecture of the
paper's VLMs (plus LLaVA), with a locally trained BPE tokenizer: no hub access.

Each :class:`TinyArch` builds a model (any machine) and a processor. The Qwen2.5-VL, Qwen3-VL,
GLM-4.1V, InternVL and LLaVA-OneVision processors hold a video processor that needs
torchvision, even for images; where torchvision is missing, :func:`in_memory_processor` builds
the processor around the image processor's PIL variant with no video processor (good for
images, and never saved), so the backend can still drive it on CPU. ``save`` writes a folder
that ``vlm-bench run --model <folder>`` loads; it needs torchvision for those five.

The request layout, the count of image tokens per view and the CLI runs used to check them
live here too: ``tests/backends/test_architectures.py`` and the scripts under ``benchmarks/``
share them.
"""

from __future__ import annotations

import importlib.util
import io
import json
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

HIDDEN, HEADS, LAYERS = 32, 2, 1
CHATML = (
    "{% for m in messages %}<|im_start|>{{ m['role'] }}\n"
    "{% if m['content'] is string %}{{ m['content'] }}{% else %}{% for c in m['content'] %}"
    "{% if c['type'] == 'image' %}IMAGE_SLOT{% elif c['type'] == 'text' %}{{ c['text'] }}"
    "{% endif %}{% endfor %}{% endif %}<|im_end|>\n{% endfor %}"
    "{% if add_generation_prompt %}<|im_start|>assistant\n{% endif %}"
)
BASE_SPECIALS = ["<pad>", "<s>", "</s>", "<unk>", "<|im_start|>", "<|im_end|>"]


def has_torchvision() -> bool:
    """True when torchvision is importable (the five processors with video need it)."""
    return importlib.util.find_spec("torchvision") is not None


def train_tokenizer(corpus: Sequence[str], specials: Sequence[str], extra: dict[str, str]) -> Any:
    """A byte-level BPE tokenizer trained on ``corpus``, with ``specials`` as special tokens and
    ``extra`` as named special tokens (``image_token`` and the like)."""
    from tokenizers import Tokenizer, decoders, models, pre_tokenizers, trainers
    from transformers import PreTrainedTokenizerFast

    bpe = Tokenizer(models.BPE(unk_token="<unk>"))
    bpe.pre_tokenizer = pre_tokenizers.ByteLevel(add_prefix_space=False)
    bpe.decoder = decoders.ByteLevel()
    trainer = trainers.BpeTrainer(
        vocab_size=2000,
        special_tokens=[*BASE_SPECIALS, *specials],
        initial_alphabet=pre_tokenizers.ByteLevel.alphabet(),
    )
    bpe.train_from_iterator(list(corpus), trainer)
    return PreTrainedTokenizerFast(
        tokenizer_object=bpe,
        bos_token="<s>",
        eos_token="<|im_end|>",
        pad_token="<pad>",
        unk_token="<unk>",
        extra_special_tokens=extra,
    )


@contextmanager
def _unchecked_processor_parts() -> Iterator[None]:
    """Let a processor be built with ``video_processor=None`` (its class check looks the video
    processor base class up, which is absent without torchvision)."""
    from transformers.processing_utils import ProcessorMixin

    original = ProcessorMixin.check_argument_for_proper_class
    ProcessorMixin.check_argument_for_proper_class = lambda self, name, arg: None  # type: ignore[method-assign]
    try:
        yield
    finally:
        ProcessorMixin.check_argument_for_proper_class = original  # type: ignore[method-assign]


@dataclass(frozen=True)
class Built:
    """A tiny model and its processor parts."""

    model: Any
    tokenizer: Any
    image_processor: Any
    processor_cls: Any
    processor_kwargs: dict[str, Any]
    video_processor: Callable[[], Any] | None
    """Builds the torchvision video processor (None: the processor has none)."""
    image_token_id: int

    def processor(self) -> Any:
        """The full processor (needs torchvision where there is a video processor)."""
        video = {} if self.video_processor is None else {"video_processor": self.video_processor()}
        return self.processor_cls(
            image_processor=self.image_processor,
            tokenizer=self.tokenizer,
            **video,
            **self.processor_kwargs,
        )

    def in_memory_processor(self) -> Any:
        """The processor without its video processor (images only; CPU without torchvision)."""
        if self.video_processor is None:
            return self.processor()
        with _unchecked_processor_parts():
            return self.processor_cls(
                image_processor=self.image_processor,
                tokenizer=self.tokenizer,
                video_processor=None,
                **self.processor_kwargs,
            )

    def save(self, out: Path) -> Path:
        """Write model and processor to ``out`` (loads with ``--model out``)."""
        self.model.save_pretrained(out)
        self.processor().save_pretrained(out)
        return out


@dataclass(frozen=True)
class TinyArch:
    """One architecture of the paper's VLMs, as a tiny random-weight model."""

    name: str
    card: str | None
    """The model card it stands for (None: LLaVA, in no card)."""
    architecture: str
    """The class AutoModelForImageTextToText loads."""
    video_processor: bool
    """The processor holds a video processor (needs torchvision)."""
    build: Callable[[Sequence[str]], Built]


def _template(slot: str) -> str:
    return CHATML.replace("IMAGE_SLOT", slot)


def _seeded(config: Any, model_cls: Any) -> Any:
    import torch

    torch.manual_seed(0)
    return model_cls(config).eval()


def _llava(corpus: Sequence[str]) -> Built:
    from transformers import (
        CLIPImageProcessor,
        CLIPVisionConfig,
        LlamaConfig,
        LlavaConfig,
        LlavaForConditionalGeneration,
        LlavaProcessor,
    )

    tok = train_tokenizer(corpus, ["<image>"], {"image_token": "<image>"})
    image_id = tok.convert_tokens_to_ids("<image>")
    config = LlavaConfig(
        vision_config=CLIPVisionConfig(
            hidden_size=HIDDEN,
            intermediate_size=64,
            num_hidden_layers=LAYERS,
            num_attention_heads=HEADS,
            image_size=32,
            patch_size=8,
            projection_dim=HIDDEN,
        ),
        text_config=LlamaConfig(**_text_config(tok)),
        image_token_id=image_id,
        vision_feature_select_strategy="default",
        vision_feature_layer=-1,
    )
    image_processor = CLIPImageProcessor(
        size={"shortest_edge": 32}, crop_size={"height": 32, "width": 32}
    )
    return Built(
        model=_seeded(config, LlavaForConditionalGeneration),
        tokenizer=tok,
        image_processor=image_processor,
        processor_cls=LlavaProcessor,
        processor_kwargs={
            "patch_size": 8,
            "vision_feature_select_strategy": "default",
            "num_additional_image_tokens": 1,
            "chat_template": _template("<image>"),
        },
        video_processor=None,
        image_token_id=image_id,
    )


def _qwen_vl(corpus: Sequence[str], version: str) -> Built:
    import transformers as tf
    from transformers.models.qwen2_vl.image_processing_pil_qwen2_vl import (
        Qwen2VLImageProcessorPil,
    )

    specials = ["<|vision_start|>", "<|vision_end|>", "<|image_pad|>", "<|video_pad|>"]
    tok = train_tokenizer(
        corpus, specials, {"image_token": "<|image_pad|>", "video_token": "<|video_pad|>"}
    )
    ids = {t: tok.convert_tokens_to_ids(t) for t in specials}
    patch = 14 if version == "2.5" else 16
    # head_dim 16: the three M-RoPE sections (t, h, w) share its 8 frequencies
    text = _text_config(tok, rope_parameters={"rope_type": "default", "mrope_section": [2, 3, 3]})
    vision = {
        "depth": LAYERS,
        "hidden_size": HIDDEN,
        "intermediate_size": 64,
        "num_heads": HEADS,
        "patch_size": patch,
        "spatial_merge_size": 2,
        "temporal_patch_size": 2,
        "out_hidden_size": HIDDEN,
    }
    common = {
        "image_token_id": ids["<|image_pad|>"],
        "video_token_id": ids["<|video_pad|>"],
        "vision_start_token_id": ids["<|vision_start|>"],
        "vision_end_token_id": ids["<|vision_end|>"],
    }
    if version == "2.5":
        vision.update(window_size=2 * patch * 2, fullatt_block_indexes=[0])
        config = tf.Qwen2_5_VLConfig(text_config=text, vision_config=vision, **common)
        model_cls, processor_cls = tf.Qwen2_5_VLForConditionalGeneration, tf.Qwen2_5_VLProcessor
        video_name = "Qwen2VLVideoProcessor"
    else:
        text["rope_parameters"] = {
            "rope_type": "default",
            "mrope_section": [2, 3, 3],
            "mrope_interleaved": True,
        }
        text["head_dim"] = HIDDEN // HEADS
        vision.update(num_position_embeddings=64, deepstack_visual_indexes=[0])
        config = tf.Qwen3VLConfig(text_config=text, vision_config=vision, **common)
        model_cls, processor_cls = tf.Qwen3VLForConditionalGeneration, tf.Qwen3VLProcessor
        video_name = "Qwen3VLVideoProcessor"
    factor = patch * 2
    image_processor = Qwen2VLImageProcessorPil(
        patch_size=patch,
        merge_size=2,
        temporal_patch_size=2,
        size={"shortest_edge": factor * factor, "longest_edge": factor * factor * 16},
    )
    return Built(
        model=_seeded(config, model_cls),
        tokenizer=tok,
        image_processor=image_processor,
        processor_cls=processor_cls,
        processor_kwargs={
            "chat_template": _template("<|vision_start|><|image_pad|><|vision_end|>")
        },
        video_processor=lambda: getattr(tf, video_name)(patch_size=patch, merge_size=2),
        image_token_id=ids["<|image_pad|>"],
    )


def _text_config(tok: Any, **extra: Any) -> dict[str, Any]:
    return {
        "hidden_size": HIDDEN,
        "intermediate_size": 64,
        "num_hidden_layers": LAYERS,
        "num_attention_heads": HEADS,
        "num_key_value_heads": HEADS,
        "vocab_size": len(tok),
        "max_position_embeddings": 8192,
        "bos_token_id": tok.bos_token_id,
        "eos_token_id": tok.eos_token_id,
        "pad_token_id": tok.pad_token_id,
        **extra,
    }


def _glm4v(corpus: Sequence[str]) -> Built:
    import transformers as tf
    from transformers.models.glm4v.image_processing_pil_glm4v import Glm4vImageProcessorPil

    marks = ["<|begin_of_image|>", "<|end_of_image|>", "<|begin_of_video|>", "<|end_of_video|>"]
    specials = [*marks, "<|image|>", "<|video|>"]
    named = {"image_token": "<|image|>", "video_token": "<|video|>"}
    tok = train_tokenizer(corpus, specials, named)
    ids = {t: tok.convert_tokens_to_ids(t) for t in specials}
    config = tf.Glm4vConfig(
        # head_dim 16, half of it rotary: the three M-RoPE sections share 4 frequencies
        text_config=_text_config(
            tok,
            rope_parameters={
                "rope_type": "default",
                "mrope_section": [1, 1, 2],
                "partial_rotary_factor": 0.5,
            },
        ),
        vision_config={
            "depth": LAYERS,
            "hidden_size": HIDDEN,
            "intermediate_size": 64,
            "num_heads": HEADS,
            "patch_size": 14,
            "image_size": 56,
            "spatial_merge_size": 2,
            "temporal_patch_size": 2,
            "out_hidden_size": HIDDEN,
        },
        image_token_id=ids["<|image|>"],
        video_token_id=ids["<|video|>"],
        image_start_token_id=ids["<|begin_of_image|>"],
        image_end_token_id=ids["<|end_of_image|>"],
        video_start_token_id=ids["<|begin_of_video|>"],
        video_end_token_id=ids["<|end_of_video|>"],
    )
    image_processor = Glm4vImageProcessorPil(
        patch_size=14,
        merge_size=2,
        temporal_patch_size=2,
        size={"shortest_edge": 28 * 28, "longest_edge": 28 * 28 * 16},
    )
    return Built(
        model=_seeded(config, tf.Glm4vForConditionalGeneration),
        tokenizer=tok,
        image_processor=image_processor,
        processor_cls=tf.Glm4vProcessor,
        processor_kwargs={
            "chat_template": _template("<|begin_of_image|><|image|><|end_of_image|>")
        },
        video_processor=lambda: tf.Glm4vVideoProcessor(patch_size=14, merge_size=2),
        image_token_id=ids["<|image|>"],
    )


def _internvl(corpus: Sequence[str]) -> Built:
    import transformers as tf
    from transformers.models.got_ocr2.image_processing_pil_got_ocr2 import (
        GotOcr2ImageProcessorPil,
    )

    named = {
        "start_image_token": "<img>",
        "end_image_token": "</img>",
        "context_image_token": "<IMG_CONTEXT>",
        "video_token": "<video>",
    }
    tok = train_tokenizer(corpus, list(named.values()), named)
    image_id = tok.convert_tokens_to_ids("<IMG_CONTEXT>")
    tile, patch = 32, 8
    seq = (tile // patch) ** 2 // 4  # 0.5 pixel-shuffle downsampling on each side
    config = tf.InternVLConfig(
        vision_config={
            "hidden_size": HIDDEN,
            "num_hidden_layers": LAYERS,
            "num_attention_heads": HEADS,
            "intermediate_size": 64,
            "image_size": [tile, tile],
            "patch_size": [patch, patch],
        },
        text_config={"model_type": "qwen2", **_text_config(tok)},
        image_token_id=image_id,
        image_seq_length=seq,
    )
    image_processor = GotOcr2ImageProcessorPil(
        size={"height": tile, "width": tile}, crop_to_patches=True, min_patches=1, max_patches=4
    )
    return Built(
        model=_seeded(config, tf.InternVLForConditionalGeneration),
        tokenizer=tok,
        image_processor=image_processor,
        processor_cls=tf.InternVLProcessor,
        processor_kwargs={"image_seq_length": seq, "chat_template": _template("<IMG_CONTEXT>")},
        video_processor=lambda: tf.InternVLVideoProcessor(size={"height": tile, "width": tile}),
        image_token_id=image_id,
    )


def _llava_onevision(corpus: Sequence[str]) -> Built:
    import transformers as tf
    from transformers.models.llava_onevision.image_processing_pil_llava_onevision import (
        LlavaOnevisionImageProcessorPil,
    )

    tok = train_tokenizer(
        corpus, ["<image>", "<video>"], {"image_token": "<image>", "video_token": "<video>"}
    )
    image_id = tok.convert_tokens_to_ids("<image>")
    tile, patch = 32, 8
    pinpoints = [[tile, tile], [tile, 2 * tile], [2 * tile, tile], [2 * tile, 2 * tile]]
    config = tf.LlavaOnevisionConfig(
        vision_config={
            "model_type": "siglip_vision_model",
            "hidden_size": HIDDEN,
            "intermediate_size": 64,
            "num_hidden_layers": LAYERS,
            "num_attention_heads": HEADS,
            "image_size": tile,
            "patch_size": patch,
            "vision_use_head": False,
        },
        text_config={"model_type": "qwen2", **_text_config(tok)},
        image_token_index=image_id,
        video_token_index=tok.convert_tokens_to_ids("<video>"),
        image_grid_pinpoints=pinpoints,
        vision_feature_select_strategy="full",
    )
    image_processor = LlavaOnevisionImageProcessorPil(
        size={"height": tile, "width": tile}, image_grid_pinpoints=pinpoints
    )
    return Built(
        model=_seeded(config, tf.LlavaOnevisionForConditionalGeneration),
        tokenizer=tok,
        image_processor=image_processor,
        processor_cls=tf.LlavaOnevisionProcessor,
        processor_kwargs={
            "num_image_tokens": (tile // patch) ** 2,
            "vision_feature_select_strategy": "full",
            "chat_template": _template("<image>"),
        },
        video_processor=lambda: tf.LlavaOnevisionVideoProcessor(
            size={"height": tile, "width": tile}
        ),
        image_token_id=image_id,
    )


ARCHS: tuple[TinyArch, ...] = (
    TinyArch("llava", None, "LlavaForConditionalGeneration", False, _llava),
    TinyArch(
        "qwen2_5_vl",
        "qwen2.5-vl-7b",
        "Qwen2_5_VLForConditionalGeneration",
        True,
        lambda corpus: _qwen_vl(corpus, "2.5"),
    ),
    TinyArch(
        "qwen3_vl",
        "qwen3-vl-8b",
        "Qwen3VLForConditionalGeneration",
        True,
        lambda corpus: _qwen_vl(corpus, "3"),
    ),
    TinyArch("glm4v", "glm-4.1v-9b-thinking", "Glm4vForConditionalGeneration", True, _glm4v),
    TinyArch("internvl", "internvl3.5-8b", "InternVLForConditionalGeneration", True, _internvl),
    TinyArch(
        "llava_onevision",
        "llava-onevision-7b",
        "LlavaOnevisionForConditionalGeneration",
        True,
        _llava_onevision,
    ),
)
"""Every architecture with a tiny build, LLaVA first."""


VIEWS = {
    "uav": "UAV camera",
    "wrist": "Wrist camera",
    "overhead": "Overhead camera",
    "side": "Side camera",
}
"""The four views and their labels, as the prompt's user turn writes them."""


def png(color: tuple[int, int, int], size: int) -> bytes:
    """A plain PNG of one colour."""
    from PIL import Image

    buf = io.BytesIO()
    Image.new("RGB", (size, size), color).save(buf, format="PNG")
    return buf.getvalue()


def four_view_requests(system: str, n: int, size: int = 112) -> list[Any]:
    """``n`` requests laid out as a run's: each view's label, then its image; then the
    instruction."""
    from vlm_bench.types.generation import GenerationRequest, ImagePart, TextPart

    out: list[Any] = []
    for i in range(n):
        parts: list[Any] = []
        for k, (view, title) in enumerate(VIEWS.items()):
            color = (60 * k, (255 - 40 * i) % 256, (30 * i) % 256)
            parts += [
                TextPart(text=f"{title} ({view}):\n"),
                ImagePart(view=view, png=png(color, size)),
            ]
        parts.append(TextPart(text=f"Instruction: put object {i} in the basket."))
        out.append(GenerationRequest(id=f"r{i}", system=system, user=tuple(parts)))
    return out


def tokens_per_view(processor: Any, image_id: int, system: str, size: int = 112) -> int:
    """Image tokens the processor gives each view of one four-view request encoded alone (all
    views share a size; LLaVA-OneVision gives an image fewer tokens when it is one of many)."""
    from PIL import Image

    from vlm_bench.backends.hf import hf_messages

    request = four_view_requests(system, 1, size)[0]
    images = [Image.open(io.BytesIO(p.png)).convert("RGB") for p in request.images()]
    text = processor.apply_chat_template(
        hf_messages(request, images), add_generation_prompt=True, tokenize=False
    )
    encoded = processor(text=[text], images=[images], return_tensors="pt")
    total = int((encoded["input_ids"] == image_id).sum())
    if total % len(VIEWS):
        raise AssertionError(f"{total} image tokens do not split over {len(VIEWS)} views")
    return total // len(VIEWS)


def image_runs(ids: Sequence[int], image_id: int) -> list[tuple[int, int]]:
    """(start, length) of each run of image tokens in a prompt."""
    runs: list[tuple[int, int]] = []
    for i, tok in enumerate(ids):
        if tok == image_id:
            if runs and runs[-1][0] + runs[-1][1] == i:
                runs[-1] = (runs[-1][0], runs[-1][1] + 1)
            else:
                runs.append((i, 1))
    return runs


def views_reaching_the_model(
    rows: Sequence[Sequence[int]], tokenizer: Any, image_id: int
) -> list[list[tuple[str, int]]]:
    """Per prompt: (the label before each image block, the block's image tokens)."""
    out: list[list[tuple[str, int]]] = []
    for ids in rows:
        seen: list[tuple[str, int]] = []
        for start, length in image_runs(ids, image_id):
            before = tokenizer.decode(list(ids[max(0, start - 12) : start]))
            label = next((view for view in VIEWS if f"({view}):" in before), "")
            seen.append((label, length))
        out.append(seen)
    return out


@contextmanager
def encoded_prompts() -> Iterator[list[list[int]]]:
    """Collect the token ids of every prompt the hf backend encodes (padding dropped)."""
    from vlm_bench.backends.hf import HfBackend

    rows: list[list[int]] = []
    real = HfBackend._encode

    def encode(self: HfBackend, batch: Any) -> Any:
        inputs = real(self, batch)
        mask = inputs["attention_mask"].bool()
        rows.extend(ids[m].tolist() for ids, m in zip(inputs["input_ids"], mask, strict=True))
        return inputs

    HfBackend._encode = encode  # type: ignore[method-assign]
    try:
        yield rows
    finally:
        HfBackend._encode = real  # type: ignore[method-assign]


def cli_run(out: Path, model: Path, batch_size: int, *extra: str) -> None:
    """``vlm-bench run --model <folder>`` on 8 episodes (standard_pick_place, seeds 0-3, both
    instructions), planning only, in this process."""
    from typer.testing import CliRunner

    from vlm_bench.cli.main import _register, app

    if not any(c.name == "run" for c in app.registered_commands):
        _register()
    args = ["run", "--model", str(model), "--task", "standard_pick_place", "--seeds", "0-3"]
    args += ["--k-shot", "0", "--no-execute", "--no-progress", "--max-new-tokens", "6"]
    args += ["--batch-size", str(batch_size), "--out", str(out), *extra]
    result = CliRunner().invoke(app, args, catch_exceptions=False)
    if result.exit_code != 0:
        raise RuntimeError(f"vlm-bench run failed ({result.exit_code}): {result.output}")


def run_outputs(run: Path) -> dict[str, str]:
    """Episode key -> raw output of a run folder's records."""
    lines = (run / "records.jsonl").read_text().splitlines()
    return {r["key"]: r["raw_output"] for r in map(json.loads, lines)}
