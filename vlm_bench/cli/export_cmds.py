"""``vlm-bench export …``: the benchmark in other tools' formats (``dataset``: a Hugging Face
dataset folder). Heavy imports happen inside the commands."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from vlm_bench.cli.options import parse_seeds, parse_suite
from vlm_bench.cli.prompt_options import (
    DEFAULT_K_SHOT,
    DEFAULT_RESOLUTION,
    DEFAULT_VIEWS,
    InstructionOption,
    KShotOption,
    NoObjectListOption,
    NoSnapshotCacheOption,
    ResolutionOption,
    SceneAsTextOption,
    SuiteOption,
    TaskOption,
    ViewsOption,
    prompt_fields,
)
from vlm_bench.cli.run_cmds import parse_instructions

export_app = typer.Typer(
    no_args_is_help=True,
    help="Export the benchmark for other harnesses (a Hugging Face dataset, ...).",
)


def dataset(
    out: Annotated[Path, typer.Argument(metavar="OUT", help="Dataset folder to write.")],
    task: TaskOption = None,
    suite: SuiteOption = None,
    seeds: Annotated[str, typer.Option(help="Seeds: 0-9 or 0,3,5.")] = "0-9",
    instruction: InstructionOption = "both",
    views: ViewsOption = DEFAULT_VIEWS,
    resolution: ResolutionOption = DEFAULT_RESOLUTION,
    k_shot: KShotOption = DEFAULT_K_SHOT,
    no_object_list: NoObjectListOption = False,
    scene_as_text: SceneAsTextOption = False,
    force: Annotated[
        bool, typer.Option("--force", help="Replace the dataset in a non-empty OUT.")
    ] = False,
    shard_rows: Annotated[int, typer.Option(help="Rows per Parquet file.")] = 100,
    no_snapshot_cache: NoSnapshotCacheOption = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """Write the episodes as a Hugging Face dataset folder (Parquet + card) that
    datasets.load_dataset(OUT) loads: one row per episode with the exact prompt a run with
    these options sends, its images, the object ids and the GT plan."""
    from vlm_bench.export.dataset_export import export_dataset
    from vlm_bench.export.options import export_options
    from vlm_bench.resources import results_dir
    from vlm_bench.storage import default_snapshot_cache

    fields = prompt_fields(views, resolution, k_shot, no_object_list, False, scene_as_text)
    del fields["images"]  # a dataset always holds the views
    options = export_options(
        tasks=tuple(task or ()),
        suite=parse_suite(suite),
        seeds=tuple(parse_seeds(seeds)),
        instructions=parse_instructions(instruction),
        **fields,
    )
    cache = None if no_snapshot_cache else default_snapshot_cache(results_dir() / "export")
    result = export_dataset(
        out, options, force=force, snapshot_cache=cache, shard_rows=shard_rows, progress=progress
    )
    typer.echo(
        f"{result.folder}: {result.rows} rows in {len(result.shards)} Parquet file(s), "
        f"{result.bytes / 1e6:.1f} MB; load with datasets.load_dataset({str(result.folder)!r})"
    )


def register(app: typer.Typer) -> None:
    """Add the ``export`` group to ``app``."""
    export_app.command()(dataset)
    app.add_typer(export_app, name="export")
