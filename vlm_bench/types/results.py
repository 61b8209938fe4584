"""``results.json``: one run's numbers in the form a leaderboard accepts (docs/protocols.md).

Written next to the records when a run or rescore finishes; its JSON Schema
(``docs/results.schema.json``) is :func:`results_json_schema`, exported from these models.
``schema_version`` changes whenever a field changes meaning or is removed; adding an optional
field keeps it. Missing values (no interval, no execution) are ``null``: JSON has no NaN.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any, Literal

from pydantic import ConfigDict, Field

from vlm_bench.types.base import Frozen
from vlm_bench.types.protocol import ProtocolMark

RESULTS_SCHEMA_VERSION = 1
"""Version of the ``results.json`` layout written by this release."""

RESULTS_FILE = "results.json"
"""The file's name in a run folder."""

InstructionName = Literal["explicit", "implicit", "both"]


class Estimate(Frozen):
    """One table value with its bootstrap interval."""

    value: float | None = Field(description="The table's value (null: no answered episode).")
    lo: float | None = Field(
        default=None, description="Interval's lower bound (null: one task, no interval)."
    )
    hi: float | None = Field(default=None, description="Interval's upper bound.")


class GroupResults(Frozen):
    """The metrics of one suite (or ``overall``) under one instruction variant."""

    group: str = Field(
        description="Suite id (base_manipulation, object_spatial, semantic, long_horizon) or "
        "overall (the unweighted mean of the suites, as the paper's Overall Average)."
    )
    n: int = Field(ge=0, description="Answered episodes the values cover.")
    complete: bool = Field(
        default=True, description="Overall only: every suite has episodes (else partial)."
    )
    metrics: dict[str, Estimate] = Field(
        description="S_plan, S_loc, S_obj, S_skill, S_total, Succ (%); exec_success (%) and "
        "S_task when plans were executed; Move_ratio and S_loc_prec where the release has them."
    )


class InstructionResults(Frozen):
    """Every group's metrics under one instruction variant (``both`` = their mean)."""

    instruction: InstructionName = Field(description="explicit, implicit or both.")
    groups: list[GroupResults] = Field(description="One entry per suite, then overall.")


class SuccAtK(Frozen):
    """Closed loop: percent of episodes whose task succeeded within rounds 0..k."""

    instruction: InstructionName = Field(description="explicit, implicit or both (pooled).")
    k: int = Field(ge=0, description="Replans allowed (0 = open-loop execution success).")
    estimate: Estimate = Field(description="Succ@k in % with its task-clustered interval.")
    n: int = Field(ge=0, description="Closed-loop episodes counted.")


class Counts(Frozen):
    """How many episodes the numbers rest on."""

    episodes: int = Field(ge=0, description="Episodes with a record.")
    answered: int = Field(ge=0, description="Episodes the backend answered (status ok).")
    errors: int = Field(ge=0, description="Episodes whose backend failed (left out of means).")
    executed: int = Field(ge=0, description="Answered episodes with an execution result.")


class ModelInfo(Frozen):
    """The model evaluated."""

    name: str = Field(description="The run's model string (--model).")
    backend: str = Field(description="Backend that served it (hf, openai, vllm, mock, ...).")
    card: dict[str, Any] | None = Field(
        default=None, description="Its model card (models/), null for a model without one."
    )


class Intervals(Frozen):
    """How the intervals were computed (report/bootstrap.py)."""

    method: str = Field(
        default="percentile bootstrap, tasks resampled within their suite",
        description="The resampling scheme.",
    )
    n_boot: int = Field(ge=1, description="Bootstrap replicates.")
    level: float = Field(gt=0, lt=1, description="Coverage (0.95 = 2.5th-97.5th percentile).")
    seed: int = Field(ge=0, description="Seed of the resampling.")


class RunResults(Frozen):
    """The content of a run's ``results.json``."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    schema_version: int = Field(
        default=RESULTS_SCHEMA_VERSION, description="Layout version of this file."
    )
    benchmark: Literal["vlm-bench"] = Field(default="vlm-bench", description="The benchmark.")
    benchmark_version: int = Field(
        ge=1, description="Benchmark version evaluated (docs/benchmark-versions.md)."
    )
    package_version: str = Field(description="vlm-bench release that wrote the file.")
    packages: dict[str, str] = Field(description="Versions of key packages (the manifest's).")
    run_id: str = Field(description="The run folder's name.")
    written: datetime = Field(description="When this file was written (UTC).")
    model: ModelInfo = Field(description="The model and its card.")
    protocol: ProtocolMark = Field(description="The run's protocol and its share of it.")
    config_hash: str = Field(description="sha256 of the run's scored settings (manifest).")
    config: dict[str, Any] = Field(description="The run's configuration (secrets redacted).")
    loop: Literal["open", "closed"] = Field(description="open or closed loop.")
    counts: Counts = Field(description="Episodes behind the numbers.")
    results: list[InstructionResults] = Field(
        description="Per instruction variant (and both), per suite and overall."
    )
    succ_at_k: list[SuccAtK] = Field(
        default_factory=list, description="Closed loop only: Succ@k for k = 0..K."
    )
    intervals: Intervals = Field(description="How the intervals were computed.")

    def overall(self, instruction: InstructionName = "both") -> GroupResults | None:
        """The overall group of one instruction row (None when the run lacks it)."""
        for row in self.results:
            if row.instruction == instruction:
                for group in row.groups:
                    if group.group == "overall":
                        return group
        return None


def results_json_schema() -> dict[str, Any]:
    """The JSON Schema of ``results.json`` (draft 2020-12, as pydantic writes it)."""
    schema = RunResults.model_json_schema(mode="serialization")
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return schema
