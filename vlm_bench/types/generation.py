"""What backends consume and produce: requests, generation settings, results."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import ConfigDict, Field, model_validator

from vlm_bench.types.base import Frozen, Utf8Str
from vlm_bench.types.plan import ArmStep, PlanStep


class TextPart(Frozen):
    """A span of prompt text."""

    type: Literal["text"] = "text"
    text: str


class ImagePart(Frozen):
    """An image of one camera view, as PNG bytes (base64 in JSON)."""

    model_config = ConfigDict(
        frozen=True, extra="forbid", ser_json_bytes="base64", val_json_bytes="base64"
    )

    type: Literal["image"] = "image"
    view: str = Field(description="Camera view the image comes from (uav, wrist, overhead, side).")
    png: bytes = Field(repr=False, description="PNG-encoded image.")


ContentPart = Annotated[TextPart | ImagePart, Field(discriminator="type")]


class RequestMeta(Frozen):
    """Episode facts for the built-in backends that need no weights (never shown to a model).

    The runner fills it for every request: ``oracle`` answers ``gt_plan``; ``random`` draws
    objects from ``object_ids``; ``blind`` and ``rules`` read only ``arm_steps`` (perfect
    language) and, for ``blind``, ``task_id`` and ``seed``. Model backends ignore it.
    """

    task_id: str = Field(default="", description="Task the episode belongs to.")
    seed: int | None = Field(default=None, description="The episode's seed.")
    gt_plan: tuple[PlanStep, ...] | None = Field(default=None, description="The episode's GT plan.")
    arm_steps: tuple[ArmStep, ...] | None = Field(
        default=None, description="The GT's ARM steps alone (what the instruction asks for)."
    )
    object_ids: tuple[str, ...] = Field(default=(), description="Ids a plan may reference.")
    round: int = Field(default=0, ge=0, description="Closed loop: the round (0 = first plan).")
    done_steps: tuple[PlanStep, ...] = Field(
        default=(), description="Closed loop: the steps executed with success so far, in order."
    )
    held: str | None = Field(default=None, description="Closed loop: what the gripper holds.")


class Turn(Frozen):
    """An earlier turn of a conversation (a closed loop's earlier rounds)."""

    model_config = ConfigDict(
        frozen=True, extra="forbid", ser_json_bytes="base64", val_json_bytes="base64"
    )

    role: Literal["user", "assistant"] = Field(description="Who spoke.")
    content: tuple[ContentPart, ...] = Field(description="Text and images, in order.")


class GenerationRequest(Frozen):
    """One prompt to complete: a system message, earlier turns (a closed loop's replans:
    multi-turn), and the user turn of text and images."""

    model_config = ConfigDict(
        frozen=True, extra="forbid", ser_json_bytes="base64", val_json_bytes="base64"
    )

    id: str = Field(min_length=1, description="Unique id of this generation (results echo it).")
    episode_id: str = Field(default="", description="Episode the prompt was built for.")
    system: str = Field(description="System message text.")
    user: tuple[ContentPart, ...] = Field(description="User turn: text and images, in order.")
    history: tuple[Turn, ...] = Field(
        default=(), description="Earlier turns, oldest first, between system and user."
    )
    json_schema: dict[str, Any] | None = Field(
        default=None, description="JSON Schema of the output, for constrained decoding."
    )
    meta: RequestMeta | None = Field(default=None, description="Episode facts for built-ins.")

    def images(self) -> list[ImagePart]:
        """Every image of the conversation, in order (earlier turns first)."""
        parts = [p for turn in self.history for p in turn.content] + list(self.user)
        return [p for p in parts if isinstance(p, ImagePart)]


class GenerationConfig(Frozen):
    """Decoding settings shared by every backend; part of the run manifest.

    Every setting that changes what a model generates is a field here, so the manifest states
    the whole decoding: model backends apply these and nothing from a checkpoint's own
    ``generation_config`` (whose end-of-sequence tokens alone are kept).
    """

    max_new_tokens: int = Field(default=512, ge=1, description="Most tokens generated.")
    temperature: float = Field(
        default=0.0, ge=0.0, allow_inf_nan=False, description="0 = greedy decoding."
    )
    top_p: float = Field(default=1.0, gt=0.0, le=1.0, description="Nucleus sampling mass.")
    top_k: int = Field(
        default=0, ge=0, description="Sample from the k likeliest tokens only; 0 = no limit."
    )
    repetition_penalty: float = Field(
        default=1.0,
        gt=0.0,
        allow_inf_nan=False,
        description="Divides the logits of tokens already in the prompt or output; 1 = none.",
    )
    seed: int = Field(default=0, ge=0, description="Sampling seed (where the backend has one).")
    constrained: bool = Field(
        default=False, description="Constrain decoding to the request's JSON Schema."
    )
    batch_size: int = Field(default=8, ge=1, description="Requests per batch (local backends).")

    @property
    def greedy(self) -> bool:
        """True when decoding is greedy (temperature 0)."""
        return self.temperature == 0.0

    def decoding(self) -> dict[str, float | int]:
        """The settings that shape each token, by their names here: ``max_new_tokens``,
        ``repetition_penalty`` always; ``temperature``, ``top_p``, ``top_k`` and ``seed`` only
        when sampling (greedy decoding ignores them). Each model backend translates exactly
        these to its own parameter names."""
        out: dict[str, float | int] = {
            "max_new_tokens": self.max_new_tokens,
            "repetition_penalty": self.repetition_penalty,
        }
        if not self.greedy:
            out.update(
                temperature=self.temperature, top_p=self.top_p, top_k=self.top_k, seed=self.seed
            )
        return out


class GenerationResult(Frozen):
    """A backend's answer to one request. Failures are recorded here, never raised."""

    id: str = Field(description="The request's id.")
    text: Utf8Str = Field(default="", description="Generated text ('' on error).")
    error: Utf8Str | None = Field(
        default=None, description="Server error, timeout, or other failure to generate; None = ok."
    )
    latency_s: float = Field(
        default=0.0,
        ge=0.0,
        description="This request's time: its own round trip where requests run concurrently "
        "(openai), else its share of the batched call that answered it (the call's time divided "
        "by its requests, so that summed over a run it gives the generation time).",
    )
    batch_latency_s: float | None = Field(
        default=None, ge=0.0, description="Wall time of the whole call (batch) that answered it."
    )
    prompt_tokens: int | None = Field(default=None, ge=0, description="Prompt tokens, if known.")
    completion_tokens: int | None = Field(default=None, ge=0, description="Generated tokens.")
    finish_reason: str | None = Field(
        default=None, description="Why generation stopped: stop, length, or backend-specific."
    )

    @model_validator(mode="after")
    def _error_not_blank(self) -> GenerationResult:
        if self.error is not None and self.error == "":
            raise ValueError("error must be None or a non-empty message")
        return self

    @property
    def ok(self) -> bool:
        """True when the backend produced text without error."""
        return self.error is None
