"""World commands: tasks, episode, render, sheet, ground-truth."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from vlm_bench.cli.options import (
    image_file,
    parse_seed,
    parse_suite,
    parse_variant,
    table_console,
    writable_file,
    writable_folder,
)
from vlm_bench.errors import ConfigError

console = Console()


def tasks(
    suite: Annotated[
        str | None, typer.Option(help="Only this suite (e.g. long_horizon, lh).")
    ] = None,
    environment: Annotated[str | None, typer.Option("--env", help="Only this environment.")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print a JSON list.")] = False,
) -> None:
    """List the benchmark tasks per suite."""
    from vlm_bench.catalog.tasks import tasks_in
    from vlm_bench.catalog.world_catalog import environment as get_env

    chosen = tasks_in(parse_suite(suite))
    if environment is not None:
        get_env(environment)  # validates the name
        chosen = [t for t in chosen if t.environment == environment]
    if as_json:
        rows = [
            {"id": t.id, "name": t.name, "suite": t.suite.value, "environment": t.environment}
            for t in chosen
        ]
        typer.echo(json.dumps(rows, indent=1))
        return
    table = Table(title=f"{len(chosen)} tasks")
    table.add_column("#", justify="right")
    table.add_column("id", no_wrap=True)
    for col in ("name", "suite", "environment", "ARM steps"):
        table.add_column(col)
    for i, t in enumerate(chosen, 1):
        table.add_row(str(i), t.id, t.name, t.suite.label, t.environment, str(len(t.arm_steps)))
    table_console(console).print(table)  # piped: as wide as the rows, nothing cut
    counts: dict[str, int] = {}
    for t in chosen:
        counts[t.suite.label] = counts.get(t.suite.label, 0) + 1
    console.print(", ".join(f"{k}: {v}" for k, v in counts.items()))


def episode(
    task: Annotated[str, typer.Argument(help="Task id (see `vlm-bench tasks`).")],
    seed: Annotated[str, typer.Option(help="Episode seed (0 = canonical layout).")] = "0",
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the full episode as JSON.")
    ] = False,
) -> None:
    """Show one episode: objects, UAV start, instructions, GT plan, goals."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.types.plan import plan_to_json

    ep = get_episode(task, parse_seed(seed))
    data: dict[str, Any] = ep.model_dump(mode="json")
    data["gt_plan"] = plan_to_json(ep.gt_plan)
    if as_json:
        typer.echo(json.dumps(data, indent=1))
        return
    console.print(f"[bold]{ep.task_id}[/] seed {ep.seed} · {ep.suite.label} · {ep.environment}")
    console.print(f"explicit: {ep.instructions.explicit}")
    console.print(f"implicit: {ep.instructions.implicit}")
    console.print(f"UAV start: pos {ep.uav_start.pos} yaw {ep.uav_start.yaw_deg:.1f}°")
    for obj in ep.objects:
        console.print(
            f"  {obj.id:<22} {obj.kind:<15} {obj.color:<10} "
            f"({obj.pos[0]:+.3f}, {obj.pos[1]:+.3f}, {obj.pos[2]:.3f})"
        )
    console.print("GT plan: " + json.dumps(data["gt_plan"]))
    console.print(
        "goals: "
        + ", ".join(
            f"{g.predicate}({g.object}{', ' + g.target if g.target else ''})" for g in ep.goals
        )
    )


def render(
    task: Annotated[str, typer.Argument(help="Task id.")],
    out: Annotated[Path, typer.Option(help="Output folder.")],
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    size: Annotated[int, typer.Option(help="Image size in pixels (square).")] = 448,
    instruction: Annotated[str, typer.Option(help="Instruction shown on the sheet.")] = "explicit",
) -> None:
    """Render the four camera views as PNGs plus a labelled 2×2 sheet."""
    from vlm_bench.episodes import get_episode
    from vlm_bench.sim.snapshot_render import render_episode, save_views

    writable_folder("--out", out)
    variant = parse_variant(instruction)
    ep = get_episode(task, parse_seed(seed))
    views = render_episode(ep, size=size)
    title = f"{ep.task_id} · seed {ep.seed} · {ep.instruction(variant)}"
    paths = save_views(views, out, title=title)
    for path in paths:
        typer.echo(str(path))


def sheet(
    out: Annotated[Path, typer.Option(help="Output PNG.")],
    suite: Annotated[str | None, typer.Option(help="Only this suite.")] = None,
    task: Annotated[list[str] | None, typer.Option(help="Task id (repeatable).")] = None,
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    view: Annotated[
        str, typer.Option(help="Camera view, or 'all' for a 2×2 per task.")
    ] = "overhead",
    size: Annotated[int, typer.Option(help="Tile size in pixels.")] = 224,
    columns: Annotated[int, typer.Option(help="Tiles per row.")] = 6,
) -> None:
    """Render a contact sheet of many tasks (one view each, or all four)."""
    from vlm_bench.catalog.tasks import get_task, tasks_in
    from vlm_bench.episodes import get_episode
    from vlm_bench.sim.snapshot_render import episode_sheet

    writable_file("--out", out, make_folder=True)
    image_file("--out", out)
    if columns < 1:
        raise ConfigError(f"--columns must be at least 1, got {columns}")
    chosen = [get_task(t) for t in task] if task else tasks_in(parse_suite(suite))
    episodes = [get_episode(t.id, parse_seed(seed)) for t in chosen]
    image = episode_sheet(episodes, view=view, size=size, columns=columns)
    out.parent.mkdir(parents=True, exist_ok=True)
    image.save(out)
    typer.echo(str(out))


def ground_truth(
    write: Annotated[bool, typer.Option("--write", help="Regenerate the committed files.")] = False,
) -> None:
    """Check (or regenerate with --write) the materialised GT under ground_truth/episodes."""
    from vlm_bench.episodes.materialise import drifted_tasks, write_ground_truth

    if write:
        paths = write_ground_truth()
        typer.echo(f"wrote {len(paths)} files")
        return
    drift = drifted_tasks()
    if drift:
        typer.echo(f"GT drift in {len(drift)} tasks: {', '.join(drift)}", err=True)
        raise typer.Exit(1)
    typer.echo("ground truth up to date")


def register(app: typer.Typer) -> None:
    """Add the world commands to ``app``."""
    app.command()(tasks)
    app.command()(episode)
    app.command()(render)
    app.command()(sheet)
    app.command("ground-truth")(ground_truth)
