"""The prompt options ``run`` and ``prompt`` share: one option set whose defaults are
:class:`~vlm_bench.types.run.RunConfig`'s, so a prompt previewed with the same options is the
prompt a run sends."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.run import RunConfig


def run_default(field: str) -> Any:
    """The default of a :class:`~vlm_bench.types.run.RunConfig` field (the CLI's default)."""
    return RunConfig.model_fields[field].default


def _generation_default(field: str) -> Any:
    return GenerationConfig.model_fields[field].default


DEFAULT_VIEWS: str = ",".join(run_default("views"))
DEFAULT_RESOLUTION: int = run_default("resolution")
DEFAULT_K_SHOT: int = run_default("k_shot")
DEFAULT_BATCH_SIZE: int = _generation_default("batch_size")
DEFAULT_MAX_NEW_TOKENS: int = _generation_default("max_new_tokens")
DEFAULT_TEMPERATURE: float = _generation_default("temperature")

TaskOption = Annotated[list[str] | None, typer.Option(help="Task id (repeatable).")]
SuiteOption = Annotated[str | None, typer.Option(help="Only this suite (e.g. lh).")]
InstructionOption = Annotated[str, typer.Option(help="explicit, implicit or both.")]
ViewsOption = Annotated[str, typer.Option("--views", help="Views shown, comma-separated.")]
ResolutionOption = Annotated[int, typer.Option("--resolution", help="Snapshot side in pixels.")]
KShotOption = Annotated[int, typer.Option("--k-shot", help="Few-shot examples in the prompt.")]
NoObjectListOption = Annotated[
    bool, typer.Option("--no-object-list", help="Do not list the scene's object ids.")
]
NoImagesOption = Annotated[
    bool, typer.Option("--no-images", help="Text only: no camera views (instruction, objects).")
]
SceneAsTextOption = Annotated[
    bool,
    typer.Option(
        "--scene-as-text",
        help="Give every object's position in the UAV body frame as text (perfect perception).",
    ),
]
NoSnapshotCacheOption = Annotated[
    bool, typer.Option("--no-snapshot-cache", help="Render the views (no shared PNG cache).")
]


def parse_views(text: str) -> tuple[str, ...]:
    """Comma-separated camera views, e.g. ``uav,wrist``."""
    views = tuple(v.strip().lower() for v in text.split(",") if v.strip())
    if not views:
        raise ConfigError("no views given; valid: " + ", ".join(VIEWS))
    for view in views:
        if view not in VIEWS:
            raise UnknownNameError("camera view", view, VIEWS)
    return views


def prompt_fields(
    views: str,
    resolution: int,
    k_shot: int,
    no_object_list: bool,
    no_images: bool,
    scene_as_text: bool,
) -> dict[str, Any]:
    """The shared options as :class:`~vlm_bench.types.run.RunConfig` fields (views checked)."""
    return {
        "views": parse_views(views),
        "resolution": resolution,
        "k_shot": k_shot,
        "object_list": not no_object_list,
        "images": not no_images,
        "scene_as_text": scene_as_text,
    }
