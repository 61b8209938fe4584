"""``vlm-bench prompt``: the exact prompt a run sends for one episode, and its images."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import typer

from vlm_bench.cli.options import parse_seed, parse_variant, writable_folder
from vlm_bench.cli.prompt_options import (
    DEFAULT_K_SHOT,
    DEFAULT_RESOLUTION,
    DEFAULT_VIEWS,
    KShotOption,
    NoImagesOption,
    NoObjectListOption,
    NoSnapshotCacheOption,
    ResolutionOption,
    SceneAsTextOption,
    ViewsOption,
    prompt_fields,
)


def prompt(
    task: Annotated[str, typer.Argument(help="Task id.")],
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    instruction: Annotated[str, typer.Option(help="explicit or implicit.")] = "explicit",
    views: ViewsOption = DEFAULT_VIEWS,
    resolution: ResolutionOption = DEFAULT_RESOLUTION,
    k_shot: KShotOption = DEFAULT_K_SHOT,
    no_object_list: NoObjectListOption = False,
    no_images: NoImagesOption = False,
    scene_as_text: SceneAsTextOption = False,
    constrained: Annotated[
        bool, typer.Option(help="Also print the JSON Schema constrained decoding gets.")
    ] = False,
    out: Annotated[
        Path | None, typer.Option(help="Write the prompt's images here as <view>.png.")
    ] = None,
    no_snapshot_cache: NoSnapshotCacheOption = False,
) -> None:
    """Print the exact prompt a run with these options sends for one episode (system and user
    turns, <image:view> where each image goes) and write its images with --out."""
    from vlm_bench.api import preview_prompt
    from vlm_bench.types.generation import GenerationConfig

    if out is not None:
        writable_folder("--out", out)
    preview = preview_prompt(
        task,
        parse_seed(seed),
        parse_variant(instruction),
        snapshot_cache=not no_snapshot_cache,
        **prompt_fields(views, resolution, k_shot, no_object_list, no_images, scene_as_text),
        generation=GenerationConfig(constrained=constrained),
    )
    sys.stdout.write(preview.text())
    schema = preview.request.json_schema
    if schema is not None:
        sys.stdout.write("\n### output schema (constrained decoding)\n")
        sys.stdout.write(json.dumps(schema, indent=1) + "\n")
    print(f"prompt hash {preview.prompt.prompt_hash}", file=sys.stderr)
    if out is not None:
        for path in preview.write_images(out):
            print(f"wrote {path}", file=sys.stderr)


def register(app: typer.Typer) -> None:
    """Add ``prompt`` to ``app``."""
    app.command()(prompt)
