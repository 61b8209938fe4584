"""``vlm-bench export sft``: planner SFT data from train seeds (docs/training.md)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from vlm_bench.cli.options import parse_seeds, parse_suite, perturb_options
from vlm_bench.cli.prompt_options import (
    DEFAULT_K_SHOT,
    DEFAULT_RESOLUTION,
    DEFAULT_VIEWS,
    InstructionOption,
    KShotOption,
    NoImagesOption,
    NoObjectListOption,
    ResolutionOption,
    SceneAsTextOption,
    SuiteOption,
    TaskOption,
    ViewsOption,
    prompt_fields,
    run_default,
)


def export_sft(
    out: Annotated[Path, typer.Argument(help="Dataset folder to write (empty, or --force).")],
    seeds: Annotated[str, typer.Option(help="Train seeds: 10-109 or 10,12 (0-9 are test).")] = (
        "10-109"
    ),
    task: TaskOption = None,
    suite: SuiteOption = None,
    instruction: InstructionOption = "both",
    views: ViewsOption = DEFAULT_VIEWS,
    resolution: ResolutionOption = DEFAULT_RESOLUTION,
    k_shot: KShotOption = DEFAULT_K_SHOT,
    no_object_list: NoObjectListOption = False,
    no_images: NoImagesOption = False,
    scene_as_text: SceneAsTextOption = False,
    perturb: Annotated[
        str | None,
        typer.Option(
            help="Also replan rows: execute each GT plan under slip=P,bump=P(,gust=N) and "
            "take the rules planner's recoveries."
        ),
    ] = None,
    max_rounds: Annotated[
        int, typer.Option(help="With --perturb: replans after round 0 (K).")
    ] = run_default("max_rounds"),
    history: Annotated[
        str, typer.Option(help="With --perturb: earlier rounds as text or with images.")
    ] = run_default("history"),
    allow_test_seeds: Annotated[
        bool, typer.Option(help="Accept seeds 0-9 (the test set); the card says so.")
    ] = False,
    force: Annotated[
        bool, typer.Option(help="Replace the dataset in a non-empty folder (other files stay).")
    ] = False,
    shard_rows: Annotated[int, typer.Option(help="Rows per Parquet file.")] = 100,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """Write planner SFT data (trl's conversational vision format) for train seeds: the GT plan
    as the answer to each episode's prompt, and with --perturb the rules planner's replans."""
    from vlm_bench.cli.run_cmds import parse_instructions
    from vlm_bench.training import export_sft as api_export
    from vlm_bench.types.run import run_config

    perturbations, gust = perturb_options(perturb, 0.0)
    closed = perturbations is not None or gust > 0
    config = run_config(
        model="sft-export",
        tasks=tuple(task or ()),
        suite=parse_suite(suite),
        seeds=tuple(parse_seeds(seeds)),
        instructions=parse_instructions(instruction),
        **prompt_fields(views, resolution, k_shot, no_object_list, no_images, scene_as_text),
        execute=closed,
        uav_noise=gust,
        loop="closed" if closed else "open",
        max_rounds=max_rounds if closed else run_default("max_rounds"),
        history=history if closed else run_default("history"),
        perturb=perturbations,
    )
    done = api_export(
        config,
        out,
        force=force,
        allow_test_seeds=allow_test_seeds,
        shard_rows=shard_rows,
        progress=progress,
    )
    kinds = ", ".join(f"{n} {kind}" for kind, n in sorted(done.counts.rows.items()))
    print(
        f"wrote {done.rows} rows ({kinds or 'none'}) from {done.counts.episodes} scenes to "
        f"{done.folder}; {len(done.counts.repeats)} left out as repeats of test episodes",
        file=sys.stderr,
    )


def add_to(group: typer.Typer) -> None:
    """Add ``sft`` to the ``export`` command group."""
    group.command("sft")(export_sft)
