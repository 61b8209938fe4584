"""``vlm-bench export demos``: VLA demonstrations as a LeRobot dataset (docs/demos.md)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from vlm_bench.cli.options import parse_seeds, parse_suite, parse_variant
from vlm_bench.cli.prompt_options import SuiteOption, TaskOption, parse_views


def export_demos(
    out: Annotated[Path, typer.Argument(help="Dataset folder to write (empty, or --force).")],
    seeds: Annotated[str, typer.Option(help="Train seeds: 10-59 or 10,12 (0-9 are test).")] = (
        "10-59"
    ),
    task: TaskOption = None,
    suite: SuiteOption = None,
    instruction: Annotated[
        str, typer.Option(help="Instruction variant stored as the task: explicit or implicit.")
    ] = "explicit",
    views: Annotated[
        str, typer.Option(help="Cameras recorded, comma-separated (uav, wrist, overhead, side).")
    ] = "wrist,overhead",
    size: Annotated[int, typer.Option(help="Image side (px, even).")] = 96,
    per_arm_step: Annotated[
        bool, typer.Option(help="One LeRobot episode per ARM step (skill-level policies).")
    ] = False,
    no_variation: Annotated[
        bool, typer.Option(help="The benchmark executor exactly: no varied speeds or hovers.")
    ] = False,
    allow_test_seeds: Annotated[
        bool, typer.Option(help="Accept seeds 0-9 (the test set).")
    ] = False,
    force: Annotated[bool, typer.Option(help="Replace the dataset in a non-empty folder.")] = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """Record the scripted executor's executions of GT plans, varied like teleoperated
    demonstrations, as a LeRobotDataset v3.0 at 20 Hz (successful executions only)."""
    from pydantic import ValidationError

    from vlm_bench.errors import option_error
    from vlm_bench.runner.progress import progress_bar
    from vlm_bench.vla.demos import DemoExportConfig, DemoVariation
    from vlm_bench.vla.demos import export_demos as api_export
    from vlm_bench.vla.demos.export import check_request, count_executions

    try:
        config = DemoExportConfig(
            tasks=tuple(task or ()),
            suite=parse_suite(suite),
            seeds=tuple(parse_seeds(seeds)),
            variant=parse_variant(instruction),
            views=parse_views(views),
            size=size,
            per_arm_step=per_arm_step,
            variation=DemoVariation.none() if no_variation else DemoVariation(),
            allow_test_seeds=allow_test_seeds,
        )
    except ValidationError as err:
        raise option_error(err, "demos option") from err
    check_request(config, out, force)  # before the bar: bad input is one line
    with progress_bar(count_executions(config), "demos", enabled=progress) as advance:
        done = api_export(config, out, force=force, on_progress=lambda _: advance(1))
    failed = ", ".join(f"{n} {code}" for code, n in sorted(done.failures.items()))
    print(
        f"wrote {done.episodes} episodes ({done.frames} frames at 20 Hz) from {done.kept} of "
        f"{done.executions} executions to {done.folder}; left out: {failed or 'none'}",
        file=sys.stderr,
    )


def add_to(group: typer.Typer) -> None:
    """Add ``demos`` to the ``export`` command group."""
    group.command("demos")(export_demos)
