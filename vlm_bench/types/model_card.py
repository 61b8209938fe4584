"""Model cards (``models/*.json``): how to run one vision-language model with vlm-bench.

A card names the checkpoint, the backend that serves it when ``--model <card>`` is given, the
``-M`` arguments each backend needs, the decoding budget, and what is known to go wrong. The
exact command lines are derived from these fields (``vlm_bench.backends.recipes``), so they
cannot drift from the arguments.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from vlm_bench.types.backend_table import card_backends
from vlm_bench.types.base import Frozen
from vlm_bench.types.parse import AnswerFormat
from vlm_bench.types.vision_tokens import VisionTokens

PROMPT_TEXT_TOKENS = 2800
"""Upper estimate of the text tokens of the longest prompt (k-shot 2, about 8.1k characters at
2.9 characters per token; JSON-heavy text tokenises at 2.5-4): with a card's image tokens and
its ``max_new_tokens`` it must fit the context length its recipe sets."""
DEFAULT_VIEWS = 4
DEFAULT_RESOLUTION = 448


class SamplingPreset(Frozen):
    """The decoding a model's authors recommend, offered beside the default greedy decoding
    (``vlm-bench run --model <card> --sampling``); greedy stays the default so that models
    are compared on the same decoding."""

    temperature: float = Field(ge=0.0, description="Sampling temperature (0 = greedy).")
    top_p: float = Field(default=1.0, gt=0.0, le=1.0, description="Nucleus sampling mass.")
    top_k: int = Field(default=0, ge=0, description="k likeliest tokens only; 0 = no limit.")
    repetition_penalty: float = Field(default=1.0, gt=0.0, description="1 = none.")
    source: str = Field(
        min_length=1, description="Where the authors give it, and what is left out."
    )


class TokenBudget(Frozen):
    """Visual tokens a card's processor spends per view (:attr:`ModelCard.vision`)."""

    resolution: int = Field(description="View side in px.")
    four_views: int = Field(description="Tokens of each view when the prompt holds four.")
    one_view: int = Field(description="Tokens of a view shown alone (--views uav).")
    recipe_views: int = Field(description="Views the card's recipe shows.")
    recipe_image_tokens: int = Field(description="Image tokens of the recipe's prompt.")


def _card_backend(name: str) -> str:
    if name not in card_backends():
        raise ValueError(f"{name!r} is not a backend a card can name; valid: {card_backends()}")
    return name


CardBackend = Annotated[str, AfterValidator(_card_backend)]
"""A backend a card can give a recipe for (the backend table's ``card`` rows)."""


class ModelCard(Frozen):
    """One model's recipe."""

    name: str = Field(
        pattern=r"^[a-z0-9][a-z0-9.\-]*$", description="Card name, used as --model <name>."
    )
    title: str = Field(min_length=1, description="The model's own name.")
    hub_id: str = Field(
        pattern=r"^[\w.\-]+/[\w.\-]+$", description="Hugging Face hub id of the checkpoint."
    )
    in_paper: bool = Field(description="One of the paper's six models (else a stand-in).")
    architecture: str = Field(
        min_length=1, description="Architecture class in the checkpoint's config.json."
    )
    backend: CardBackend = Field(description="Backend --model <name> selects.")
    dtype: Literal["bfloat16", "float16", "float32"] = Field(description="Weights dtype.")
    remote_code: bool = Field(description="Needs the checkpoint repo's own Python code.")
    images: str = Field(
        min_length=1, description="How the processor sizes a view, and the -M limit it takes."
    )
    max_new_tokens: int = Field(ge=1, description="Decoding budget the recipe runs with.")
    run_options: tuple[str, ...] = Field(
        default=(), description="Other vlm-bench run options the recipe needs (--views uav)."
    )
    hf_args: dict[str, str] | None = Field(
        default=None, description="-M arguments of the hf backend (None: hf cannot serve it)."
    )
    vllm_args: dict[str, str] | None = Field(
        default=None, description="-M arguments of the vllm backend (also the server's flags)."
    )
    unsupported: dict[CardBackend, str] = Field(
        default_factory=dict, description="Backends that cannot serve it, and why."
    )
    quirks: tuple[str, ...] = Field(default=(), description="Known problems and their remedies.")
    vision: VisionTokens = Field(description="How the processor turns a view into tokens.")
    sampling: SamplingPreset | None = Field(
        default=None, description="The authors' recommended decoding (None: they decode greedily)."
    )
    answer_format: AnswerFormat | None = Field(
        default=None,
        description="Documented reasoning/answer tags; output in that form parses as valid.",
    )

    @model_validator(mode="after")
    def _recipes_match_support(self) -> ModelCard:
        for backend, args in (("hf", self.hf_args), ("vllm", self.vllm_args)):
            if (args is None) != (backend in self.unsupported):
                raise ValueError(
                    f"{backend}_args must be given exactly when {backend!r} is not in unsupported"
                )
        if self.backend in self.unsupported:
            raise ValueError(f"backend {self.backend!r} is listed as unsupported")
        if "openai" in self.unsupported and "vllm" not in self.unsupported:
            raise ValueError("a model vLLM runs can be served to the openai backend by vllm serve")
        return self

    def _option(self, name: str) -> str | None:
        words = list(self.run_options)
        return words[words.index(name) + 1] if name in words[:-1] else None

    def token_budget(self, resolution: int | None = None) -> TokenBudget:
        """Visual tokens per view at ``resolution`` (default: the recipe's, else 448 px)."""
        recipe_size = int(self._option("--resolution") or DEFAULT_RESOLUTION)
        size = resolution or recipe_size
        views = self._option("--views")
        n = len(views.split(",")) if views else DEFAULT_VIEWS
        return TokenBudget(
            resolution=size,
            four_views=self.vision.tokens(size, 4),
            one_view=self.vision.tokens(size, 1),
            recipe_views=n,
            recipe_image_tokens=n * self.vision.tokens(recipe_size, n),
        )

    def args_for(self, backend: str) -> dict[str, str]:
        """The card's ``-M`` arguments for ``backend`` (none for openai and other backends)."""
        args = {"hf": self.hf_args, "vllm": self.vllm_args}.get(backend)
        return dict(args or {})
