"""The ``execute`` command: execute one plan in the simulator, print its outcome, film it."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.console import Console
from rich.table import Table

from vlm_bench.cli.options import finite, parse_seed, parse_variant, writable_file
from vlm_bench.errors import ConfigError

if TYPE_CHECKING:
    from vlm_bench.runner.task_execution import ExecutedPlan
    from vlm_bench.types.plan import ArmStep, UavStep

console = Console()


def _step_text(step: UavStep | ArmStep) -> str:
    if step.tasktype == "UAV":
        distance = f" {step.distance:g} m" if step.distance is not None else ""
        return f"move {step.direction.value}{distance}"
    target = f" → {step.target}" if step.target else ""
    return f"{step.skill} {step.object}{target}"


def _print_execution(execution: ExecutedPlan) -> None:
    result, episode = execution.result, execution.episode
    noise = f" · uav_noise {execution.uav_noise:g} N" if execution.uav_noise else ""
    console.print(
        f"[bold]{episode.task_id}[/] seed {episode.seed} · {execution.variant} · plan: "
        f"{execution.source} ({len(execution.plan)} steps){noise}",
        highlight=False,
    )
    table = Table(show_edge=False)
    for name, justify in (
        ("#", "right"),
        ("agent", "left"),
        ("step", "left"),
        ("status", "left"),
        ("time (s)", "right"),
        ("note", "left"),
    ):
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    colour = {"ok": "green", "failed": "red", "skipped": "dim"}
    for step, outcome in zip(execution.plan, result.steps, strict=True):
        note = outcome.reason or ""
        if outcome.collisions:
            note = (note + "; " if note else "") + "touched " + ", ".join(outcome.collisions)
        table.add_row(
            str(outcome.index),
            outcome.agent,
            _step_text(step),
            f"[{colour[outcome.status]}]{outcome.status}[/]",
            f"{outcome.duration_s:.1f}",
            note,
        )
    console.print(table)
    goals = "  ".join(
        f"{'[green]✓' if ok else '[red]✗'}[/] {label}"
        for label, ok in zip(execution.goal_labels, result.goals, strict=True)
    )
    console.print(f"goals: {goals or 'none'}", highlight=False)
    line = f"exec_success: {'yes' if result.exec_success else 'no'}  S_task={result.s_task:.1f}"
    if result.scores is not None:
        s = result.scores
        line += (
            f"  S_pos={s.s_pos:.1f}  S_arm={s.s_arm:.1f}  S_safe={s.s_safe:.1f}  VLA={s.total:.1f}"
        )
    console.print(
        line + f"  (simulated {result.sim_time_s:.1f} s, wall {result.wall_time_s:.1f} s)",
        highlight=False,
    )
    if result.failure_reason:
        console.print(f"failure: {result.failure_reason}", highlight=False, soft_wrap=True)


def _read_plan(plan: str | None) -> tuple[str | None, str]:
    """(plan text or None for the GT plan, its source name)."""
    if plan is None or plan.strip().lower() == "gt":
        return None, "GT"
    from vlm_bench.catalog.files import not_utf8

    path = Path(plan)
    try:
        return path.read_text(encoding="utf-8"), path.name
    except OSError as exc:
        raise ConfigError(f"cannot read plan file {plan}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:  # a garbled step must not run
        raise ConfigError(f"plan file {plan}: {not_utf8(exc)}") from None


def execute(
    task: Annotated[str, typer.Argument(help="Task id.")],
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    plan: Annotated[
        str | None,
        typer.Option(
            help="Plan file in the paper's JSON format, or 'gt' (default) for the GT plan."
        ),
    ] = None,
    variant: Annotated[
        str,
        typer.Option(
            "--variant",
            "--instruction",
            help="explicit or implicit (a label: both variants share the scene and goals).",
        ),
    ] = "explicit",
    uav_noise: Annotated[
        float, typer.Option(help="Gust force std on the UAV in N (seeded per episode, as in runs).")
    ] = 0.0,
    video: Annotated[
        Path | None,
        typer.Option(help="Write a video: .mp4 (needs the video extra) or .gif."),
    ] = None,
    camera: Annotated[
        str | None,
        typer.Option(help="Camera filmed with --video: uav, wrist, overhead, side (default)."),
    ] = None,
    fps: Annotated[float, typer.Option(help="Video frames per second (at most 20).")] = 10.0,
    size: Annotated[int, typer.Option(help="Video frame side in pixels.")] = 480,
    shadows: Annotated[
        bool, typer.Option(help="Render shadows in the video (2-3x slower per frame on a CPU).")
    ] = True,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the ExecutionResult JSON.")
    ] = False,
) -> None:
    """Execute one plan (a file, or the GT plan) in the simulator; optionally film it."""
    from vlm_bench.api import execute as api_execute
    from vlm_bench.sim.mujoco_log import route_mujoco_log

    finite("--uav-noise", uav_noise)
    finite("--fps", fps)
    if video is None and camera is not None:
        raise ConfigError(f"--camera {camera} chooses the camera of --video; give --video too")
    if video is not None:  # before the simulation: its outcome must not be lost to a bad path
        writable_file("--video", video, make_folder=False)
    text, source = _read_plan(plan)
    route_mujoco_log()
    result = api_execute(
        task,
        parse_seed(seed),
        text,
        source=source,
        instruction=parse_variant(variant),
        uav_noise=uav_noise,
        video=video,
        camera=camera or "side",
        fps=fps,
        size=size,
        shadows=shadows,
    )
    if as_json:
        typer.echo(result.result.model_dump_json(indent=1))
    else:
        _print_execution(result)
    if result.video is not None:
        print(
            f"video: {result.video} ({result.frames} frames)",
            file=sys.stderr if as_json else sys.stdout,
        )


def register(app: typer.Typer) -> None:
    """Add the ``execute`` command to ``app``."""
    app.command()(execute)
