"""``vlm-bench prompt``: the exact prompt a run sends for one episode, and its images."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Annotated

import typer

from vlm_bench.cli.options import parse_seed, parse_variant, writable_folder
from vlm_bench.cli.run_cmds import parse_views

_VIEWS = "uav,wrist,overhead,side"


def prompt(
    task: Annotated[str, typer.Argument(help="Task id.")],
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    instruction: Annotated[str, typer.Option(help="explicit or implicit.")] = "explicit",
    views: Annotated[str, typer.Option(help="Views shown, comma-separated.")] = _VIEWS,
    resolution: Annotated[int, typer.Option(help="Snapshot side in pixels.")] = 448,
    k_shot: Annotated[int, typer.Option(help="Few-shot examples in the prompt.")] = 2,
    no_object_list: Annotated[
        bool, typer.Option("--no-object-list", help="Do not list the scene's object ids.")
    ] = False,
    no_images: Annotated[
        bool,
        typer.Option("--no-images", help="Text only: no camera views (instruction, objects)."),
    ] = False,
    scene_as_text: Annotated[
        bool,
        typer.Option(
            "--scene-as-text",
            help="Give every object's position in the UAV body frame as text (perfect perception).",
        ),
    ] = False,
    constrained: Annotated[
        bool, typer.Option(help="Also print the JSON Schema constrained decoding gets.")
    ] = False,
    out: Annotated[
        Path | None, typer.Option(help="Write the prompt's images here as <view>.png.")
    ] = None,
    no_snapshot_cache: Annotated[
        bool,
        typer.Option("--no-snapshot-cache", help="Render the views (no shared PNG cache)."),
    ] = False,
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
        views=parse_views(views),
        resolution=resolution,
        k_shot=k_shot,
        object_list=not no_object_list,
        images=not no_images,
        scene_as_text=scene_as_text,
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
