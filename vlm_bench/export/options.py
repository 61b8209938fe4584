"""What an export holds: the run's episode selection and the options that change a prompt."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from vlm_bench.types.base import Frozen
from vlm_bench.types.prompt import VIEWS, Views
from vlm_bench.types.run import RunConfig, run_config
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant, Suite

EXPORT_MODEL = "dataset-export"
"""The model string of the run configuration an export builds its prompts with (a label: no
model is called)."""

DEFAULT_EXPORT_SEEDS: tuple[int, ...] = tuple(range(10))
"""Seeds exported by default: the committed ground truth's."""


def _run_default(field: str) -> Any:
    return RunConfig.model_fields[field].default


class ExportOptions(Frozen):
    """Episode selection and prompt options of an export (the names of ``vlm-bench run``'s
    options; recorded in the dataset card)."""

    tasks: tuple[str, ...] = Field(default=(), description="Task ids; empty = all (or suite).")
    suite: Suite | None = Field(default=None, description="Only this suite (when no tasks).")
    seeds: tuple[int, ...] = Field(
        default=DEFAULT_EXPORT_SEEDS, min_length=1, description="Episode seeds."
    )
    instructions: tuple[InstructionVariant, ...] = Field(
        default=INSTRUCTION_VARIANTS, min_length=1, description="Instruction variants."
    )
    views: Views = Field(default=VIEWS, min_length=1, description="Views shown, in order.")
    resolution: int = Field(
        default=_run_default("resolution"), ge=16, le=4096, description="Snapshot side (px)."
    )
    k_shot: int = Field(
        default=_run_default("k_shot"), ge=0, description="Few-shot examples in the prompt."
    )
    object_list: bool = Field(default=True, description="List the scene's object ids.")
    scene_as_text: bool = Field(
        default=False, description="Give object positions in the UAV body frame as text."
    )

    def run_config(self) -> RunConfig:
        """The run configuration whose prompts the export holds (validated).

        Raises:
            ConfigError: Names the first invalid option.
        """
        return run_config(model=EXPORT_MODEL, **self.model_dump())


def export_options(**fields: Any) -> ExportOptions:
    """Build :class:`ExportOptions`, turning validation errors into a one-line ConfigError.

    Raises:
        ConfigError: Names the first invalid option and why.
    """
    from pydantic import ValidationError

    from vlm_bench.errors import option_error

    try:
        return ExportOptions(**fields)
    except ValidationError as exc:
        raise option_error(exc, "export option") from None
