"""Parsed model output: the plan, per-step validity, error codes and the repair tier.

The error codes are a closed set, documented here and nowhere else (:class:`ParseCode`).
"""

from __future__ import annotations

from enum import StrEnum
from typing import Literal

from pydantic import Field, JsonValue

from vlm_bench.types.base import Frozen, Utf8Str
from vlm_bench.types.plan import ArmStep, Direction, UavStep

ParseTier = Literal["valid", "repaired", "invalid"]
"""``valid``: the raw text is JSON that validates against the plan schema and every step is valid;
``repaired``: a plan was obtained after deterministic repair and normalisation;
``invalid``: no usable plan."""


class ParseCode(StrEnum):
    """Every error code the parser emits. Plan-level codes first, then per-step codes."""

    # Plan level (ParseResult.errors).
    EMPTY = "empty"
    """The output is blank."""
    NO_JSON = "no_json"
    """No JSON array or object could be found in the output."""
    NOT_A_PLAN = "not_a_plan"
    """JSON was found but it holds no step objects (e.g. a list of strings, an unrelated object)."""
    EMPTY_PLAN = "empty_plan"
    """The plan array has no elements."""
    TRUNCATED = "truncated"
    """The output ends inside an open JSON array/object (closed by repair, or unusable)."""
    SCHEMA = "schema"
    """The plan as extracted violates the plan JSON Schema (spelling, type or validity errors)."""
    TOO_LONG = "too_long"
    """The plan has more steps than the schema allows (``MAX_PLAN_STEPS``); it is not used."""
    ERROR = "error"
    """Parsing or scoring this output raised (a bug in the harness); ``ParseResult.detail`` says
    what. The output counts as having no plan."""
    # Step level (ParsedStep.errors).
    NOT_AN_OBJECT = "not_an_object"
    """The array element is not a JSON object. Step invalid."""
    MISSING_FIELD = "missing_field"
    """A required field (tasktype, direction, skill, object) is absent or null. Step invalid."""
    UNKNOWN_TASKTYPE = "unknown_tasktype"
    """The tasktype is not an agent of the skill library (UAV, ARM). Step invalid."""
    UNKNOWN_DIRECTION = "unknown_direction"
    """The direction is none of the allowed values or their aliases. Step invalid."""
    UNKNOWN_SKILL = "unknown_skill"
    """The skill is not in the library, or belongs to the other agent. Step invalid."""
    UNKNOWN_OBJECT = "unknown_object"
    """An object/target id is not in the scene (hallucination). The step stays valid."""
    BAD_VALUE = "bad_value"
    """A field has the wrong JSON type or is out of range: invalid if the field is required,
    otherwise the value is dropped and the step stays valid (e.g. ``distance: -1``)."""


class Repair(StrEnum):
    """Deterministic repairs the parser applied to get a plan, in the order they apply."""

    DECODE_STRING = "decode_string"
    """The output was a JSON string that itself holds the plan."""
    STRIP_THINK = "strip_think"
    """Removed ``<think>``/``<thinking>``/``<reasoning>`` blocks (closed or not)."""
    STRIP_FENCE = "strip_fence"
    """Took the content of a Markdown code fence."""
    EXTRACT = "extract"
    """Cut the JSON out of surrounding prose."""
    JSON_REPAIR = "json_repair"
    """Fixed the JSON syntax with json-repair (quotes, commas, Python literals, truncation)."""
    JOIN_OBJECTS = "join_objects"
    """Joined several top-level step objects (JSON lines) into one plan."""
    UNWRAP = "unwrap"
    """Unwrapped ``{"plan": [...]}``-style wrappers, a nested list, or a single step object."""
    WINDOW = "window"
    """The output is longer than the parser reads: only its end (then its start) was searched
    (``MAX_SEARCH_CHARS``)."""


class ParsedStep(Frozen):
    """One element of the predicted plan, normalised, in array order."""

    index: int = Field(ge=0, description="Position in the plan array (subtask numbers ignored).")
    tasktype: Literal["UAV", "ARM"] | None = Field(description="Agent, or None when unknown.")
    direction: Direction | None = Field(default=None, description="Canonical direction (UAV).")
    skill: str | None = Field(default=None, description="Canonical skill name, when resolved.")
    object: str | None = Field(
        default=None, description="Object id (scene id when matched); ARM and invalid steps only."
    )
    target: str | None = Field(default=None, description="Target object id, if any.")
    distance: float | None = Field(default=None, description="UAV distance (m), if valid.")
    valid: bool = Field(description="Known tasktype and every required field allowed.")
    errors: tuple[ParseCode, ...] = Field(default=(), description="Per-step codes.")
    raw: JsonValue = Field(default=None, description="The element as the model wrote it.")

    def to_step(self) -> UavStep | ArmStep | None:
        """The typed plan step, or None for an invalid step."""
        if not self.valid:
            return None
        if self.tasktype == "UAV" and self.direction is not None:
            return UavStep(direction=self.direction, distance=self.distance)
        if self.tasktype == "ARM" and self.object is not None and self.skill is not None:
            return ArmStep(object=self.object, skill=self.skill, target=self.target)
        return None


class AnswerFormat(Frozen):
    """A model's documented output format: a reasoning block, then the answer in a tag
    (GLM-4.1V-Thinking: ``<think>…</think><answer>…</answer>``). Output in exactly this form is
    not repaired: the answer is parsed as if it were the whole output (see
    :mod:`vlm_bench.parsing.answer_tag`)."""

    reasoning: str = Field(pattern=r"^[a-z_]+$", description="Reasoning tag name (think).")
    answer: str = Field(pattern=r"^[a-z_]+$", description="Answer tag name (answer).")


class ParseResult(Frozen):
    """What the parser made of one model output. Never raised; always recorded."""

    tier: ParseTier = Field(description="valid | repaired | invalid (see ParseTier).")
    steps: tuple[ParsedStep, ...] = Field(default=(), description="All steps, in array order.")
    errors: tuple[ParseCode, ...] = Field(default=(), description="Plan-level codes.")
    repairs: tuple[Repair, ...] = Field(default=(), description="Repairs applied, in order.")
    reasoning: Utf8Str | None = Field(
        default=None,
        description="The reasoning block of output in the model's documented answer format.",
    )
    detail: Utf8Str | None = Field(default=None, description="What raised (code ``error`` only).")

    @property
    def n_steps(self) -> int:
        """Number of steps, invalid ones included (K of the metrics)."""
        return len(self.steps)

    @property
    def usable(self) -> bool:
        """True when the output held a plan (tier valid or repaired)."""
        return self.tier != "invalid"

    @property
    def n_invalid(self) -> int:
        """Number of invalid steps."""
        return sum(not s.valid for s in self.steps)

    def valid_steps(self) -> list[UavStep | ArmStep]:
        """The valid steps as typed plan steps, in order (invalid ones skipped)."""
        return [step for s in self.steps if (step := s.to_step()) is not None]

    def all_errors(self) -> tuple[ParseCode, ...]:
        """Plan-level codes followed by every step's codes, duplicates removed, order kept."""
        seen = dict.fromkeys(self.errors)
        for s in self.steps:
            seen.update(dict.fromkeys(s.errors))
        return tuple(seen)
