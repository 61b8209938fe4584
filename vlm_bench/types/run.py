"""Run configuration and run manifest: what a run evaluates and how it was produced.

A run folder is identified by its :class:`RunConfig`; :meth:`RunConfig.config_hash` covers every
field that changes an episode's result or the set of episodes. It leaves out what only changes
how fast results arrive (``generation.batch_size`` and the backend arguments its backend declares
operational, such as ``concurrency`` or ``timeout_s``: passed in as ``operational``, see
``vlm_bench.backends.operational_args``) and secrets (backend arguments whose name contains
``key``, ``token``, ``secret`` or ``password``, which are also redacted in the saved manifest), so a
run can be resumed with a different batch size, a longer timeout or a fresh API key.

Fields added after the first release enter the hash only when set off their default, at any
depth (the one rule of :mod:`~vlm_bench.types.config_hash`), so configurations that could be
written before they existed keep their hash (and their default run folder). ``benchmark_version``
enters it from version 2 on: every configuration of a new benchmark version gets a new hash
(and default run folder), while a version-1 configuration, read from a manifest that predates
versions, keeps the hash it was written with.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from collections.abc import Collection
from datetime import datetime
from typing import Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from vlm_bench.errors import option_error
from vlm_bench.types.base import FiniteFrozen, Frozen
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION, FIRST_VERSION
from vlm_bench.types.closed_loop import HistoryMode, LoopConfig, LoopMode, PerturbConfig
from vlm_bench.types.config_hash import VALUE_BEFORE, stable_fields
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.prompt import VIEWS, PromptConfig, Views
from vlm_bench.types.protocol import ProtocolMark
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant, Suite

RUN_SCHEMA_VERSION = 1
"""Version of the manifest layout written by this release."""

_SECRET = re.compile(r"key|token|secret|password", re.IGNORECASE)
REDACTED = "***"


def is_secret_arg(name: str) -> bool:
    """True for backend arguments that hold credentials (redacted in manifests)."""
    return bool(_SECRET.search(name))


def non_finite_field(value: Any, path: str = "") -> tuple[str, float] | None:
    """The dotted path and value of the first NaN or infinite float in ``value`` (a model,
    mapping or sequence, walked recursively), or None: JSON has no such numbers."""
    if isinstance(value, float):
        return None if math.isfinite(value) else (path, value)
    if isinstance(value, BaseModel):
        items: Any = ((name, getattr(value, name)) for name in type(value).model_fields)
    elif isinstance(value, dict):
        items = value.items()
    elif isinstance(value, (list, tuple)):
        items = enumerate(value)
    else:
        return None
    for key, item in items:
        found = non_finite_field(item, f"{path}.{key}" if path else str(key))
        if found is not None:
            return found
    return None


class RunConfig(FiniteFrozen):
    """Everything that defines a run: model, episode selection, prompt, decoding, scoring."""

    model: str = Field(min_length=1, description="Model string: HF id/path, openai/<name>, ...")
    backend_args: dict[str, str] = Field(
        default_factory=dict, description="Backend arguments (-M key=value)."
    )
    tasks: tuple[str, ...] = Field(default=(), description="Task ids; empty = all (or suite).")
    suite: Suite | None = Field(default=None, description="Only this suite (when no tasks).")
    seeds: tuple[int, ...] = Field(default=(0,), min_length=1, description="Episode seeds.")
    instructions: tuple[InstructionVariant, ...] = Field(
        default=INSTRUCTION_VARIANTS, min_length=1, description="Instruction variants evaluated."
    )
    views: Views = Field(default=VIEWS, min_length=1, description="Views shown.")
    resolution: int = Field(default=448, ge=16, le=4096, description="Snapshot side (px).")
    labels: bool = Field(default=True, description="Draw set-of-marks labels on shared ids.")
    k_shot: int = Field(default=2, ge=0, description="Few-shot examples in the system prompt.")
    few_shot_seed: int = Field(default=0, ge=0, description="Seed of the few-shot selection.")
    object_list: bool = Field(default=True, description="List the scene's object ids.")
    images: bool = Field(
        default=True, description="Show the camera views (False: text only, --no-images)."
    )
    scene_as_text: bool = Field(
        default=False, description="Give object positions in the UAV body frame as text."
    )
    generation: GenerationConfig = Field(
        default_factory=GenerationConfig, description="Decoding settings (incl. constrained)."
    )
    scoring: ScoringConfig = Field(default_factory=ScoringConfig, description="Metric options.")
    execute: bool = Field(
        default=True, description="Execute every valid predicted plan in the simulator."
    )
    uav_noise: float = Field(
        default=0.0, ge=0, description="Gust force std on the UAV (N) during execution."
    )
    benchmark_version: int = Field(
        default=BENCHMARK_VERSION,
        ge=FIRST_VERSION,
        description="Benchmark version evaluated: tasks, GT, prompts, metrics "
        "(docs/benchmark-versions.md); 1 in manifests written before versions were recorded.",
    )
    loop: LoopMode = Field(
        default="open", description="open: one plan; closed: replan after a failed round."
    )
    max_rounds: int = Field(default=3, ge=1, le=20, description="Closed loop: replans (K).")
    step_budget: int | None = Field(
        default=None, ge=1, description="Closed loop: steps over all rounds (None: 3 x GT)."
    )
    perturb: PerturbConfig | None = Field(
        default=None, description="Seeded slips and bumps during execution (None: none)."
    )
    history: HistoryMode = Field(
        default="text",
        description="Closed loop: earlier rounds as text with only the current views, or "
        "with every round's views (images).",
    )

    @field_validator("seeds")
    @classmethod
    def _canonical_seeds(cls, seeds: tuple[int, ...]) -> tuple[int, ...]:
        if any(s < 0 for s in seeds):
            raise ValueError("seeds must be non-negative")
        return tuple(sorted(set(seeds)))

    @field_validator("tasks")
    @classmethod
    def _unique_tasks(cls, tasks: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(dict.fromkeys(tasks))

    @field_validator("instructions")
    @classmethod
    def _canonical_instructions(
        cls, variants: tuple[InstructionVariant, ...]
    ) -> tuple[InstructionVariant, ...]:
        return tuple(v for v in INSTRUCTION_VARIANTS if v in variants)

    @model_validator(mode="after")
    def _tasks_or_suite(self) -> RunConfig:
        if self.tasks and self.suite is not None:
            raise ValueError("give tasks or a suite, not both")
        return self

    @model_validator(mode="after")
    def _finite_numbers(self) -> RunConfig:
        found = non_finite_field(self)
        if found is not None:
            raise ValueError(f"{found[0]} must be a finite number, got {found[1]}")
        return self

    @model_validator(mode="after")
    def _noise_needs_execution(self) -> RunConfig:
        if self.uav_noise > 0 and not self.execute:
            raise ValueError("uav_noise > 0 needs execute (gusts act only while plans execute)")
        return self

    @model_validator(mode="after")
    def _loop_options(self) -> RunConfig:
        if self.loop == "closed" and not self.execute:
            raise ValueError("loop closed needs execute (a replan starts where execution failed)")
        if self.perturb is not None and not self.execute:
            raise ValueError("perturb needs execute (perturbations act while plans execute)")
        if self.loop == "open" and (
            self.max_rounds != 3 or self.step_budget is not None or self.history != "text"
        ):
            raise ValueError("max_rounds, step_budget and history need loop closed")
        return self

    def loop_config(self) -> LoopConfig:
        """The closed loop's settings."""
        return LoopConfig(max_rounds=self.max_rounds, step_budget=self.step_budget)

    def executor_config(self) -> ExecutorConfig:
        """The executor's settings of every execution of the run (gusts, perturbations)."""
        return ExecutorConfig(uav_noise=self.uav_noise, perturb=self.perturb)

    def prompt_config(self, variant: InstructionVariant) -> PromptConfig:
        """The prompt options of one instruction variant."""
        return PromptConfig(
            k_shot=self.k_shot,
            few_shot_seed=self.few_shot_seed,
            views=self.views if self.images else (),
            object_list=self.object_list,
            scene_as_text=self.scene_as_text,
            instruction=variant,
        )

    def hashed_fields(self, operational: Collection[str] = ()) -> dict[str, Any]:
        """The JSON payload :meth:`config_hash` covers (see the module docstring).

        Args:
            operational: The backend's operational argument names (left out).
        """
        data = stable_fields(self)
        data["backend_args"] = {
            k: v
            for k, v in sorted(self.backend_args.items())
            if not is_secret_arg(k) and k not in operational
        }
        data["generation"].pop("batch_size", None)
        if data["benchmark_version"] == FIRST_VERSION:
            del data["benchmark_version"]
        return data

    def config_hash(self, operational: Collection[str] = ()) -> str:
        """sha256 (hex) of :meth:`hashed_fields` as canonical JSON."""
        fields = self.hashed_fields(operational)
        text = json.dumps(fields, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    def short_hash(self, operational: Collection[str] = ()) -> str:
        """First 8 hex digits of :meth:`config_hash`, used in default run names."""
        return self.config_hash(operational)[:8]

    def redacted(self) -> RunConfig:
        """A copy whose secret backend arguments are replaced by ``***`` (for the manifest)."""
        args = {k: (REDACTED if is_secret_arg(k) else v) for k, v in self.backend_args.items()}
        return self.model_copy(update={"backend_args": args})


def config_differences(
    old: RunConfig, new: RunConfig, operational: Collection[str] = ()
) -> list[str]:
    """Dotted names of the hashed fields whose values differ (``generation.max_new_tokens``)."""
    return _diff(old.hashed_fields(operational), new.hashed_fields(operational), "")


def _diff(a: Any, b: Any, prefix: str) -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        out: list[str] = []
        for key in sorted(set(a) | set(b), key=str):
            out.extend(_diff(a.get(key), b.get(key), f"{prefix}{key}."))
        return out
    return [] if a == b else [prefix.rstrip(".")]


def run_config(**fields: Any) -> RunConfig:
    """Build a :class:`RunConfig`, turning validation errors into a one-line ConfigError.

    Raises:
        ConfigError: Names the first invalid field and why.
    """
    try:
        return RunConfig(**fields)
    except ValidationError as exc:
        raise option_error(exc, "run option") from None


class DataHashes(Frozen):
    """sha256 digests of the shipped data folders a run depends on."""

    prompts: str = Field(description="Files under prompts/ (templates, few-shot examples).")
    skills: str = Field(description="Files under skills/ (the skill library).")
    ground_truth: str = Field(description="Files under ground_truth/ (tasks, world, GT).")


class RunManifest(Frozen):
    """``manifest.json`` of a run folder: config and provenance, written when the run starts."""

    # Manifests are read back by later releases: ignore fields this release does not know.
    model_config = ConfigDict(frozen=True, extra="ignore", allow_inf_nan=False)

    schema_version: int = Field(default=RUN_SCHEMA_VERSION, description="Manifest layout version.")
    run_id: str = Field(description="Run id (the run folder's name).")
    config: RunConfig = Field(description="The run's configuration (secrets redacted).")
    config_hash: str = Field(description="RunConfig.config_hash() at creation.")
    operational_args: tuple[str, ...] = Field(
        default=(), description="Backend arguments left out of config_hash (the backend's own)."
    )
    backend: str = Field(description="Backend that serves the model (hf, openai, oracle, ...).")
    data: DataHashes = Field(description="Digests of prompts/, skills/, ground_truth/.")
    packages: dict[str, str] = Field(description="Versions of vlm-bench and key dependencies.")
    git_revision: str | None = Field(default=None, description="Commit (+dirty) if in a checkout.")
    python: str = Field(default="", description="Python version.")
    platform: str = Field(default="", description="OS and machine.")
    created: datetime = Field(description="When the run folder was created (UTC).")
    protocol: ProtocolMark | None = Field(
        default=None,
        description="The run's stated protocol and its share of it (None: written before "
        "protocols were recorded; vlm_bench.types.protocol_match.manifest_protocol derives it).",
    )

    @model_validator(mode="before")
    @classmethod
    def _older_fields(cls, data: Any) -> Any:
        # A manifest lists every field it knew; one without a later scoring field was written
        # before it existed, when every run scored the earlier way; one without a benchmark
        # version was written by version 1.
        config = data.get("config") if isinstance(data, dict) else None
        scoring = config.get("scoring") if isinstance(config, dict) else None
        if isinstance(scoring, dict):
            for (model, name), before in VALUE_BEFORE.items():
                if model == "ScoringConfig":
                    scoring.setdefault(name, before)
        if isinstance(config, dict):
            config.setdefault("benchmark_version", FIRST_VERSION)
        return data
