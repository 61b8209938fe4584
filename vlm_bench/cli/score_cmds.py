"""Commands that score without a model: ``rescore`` (a run from its response cache) and
``score`` (one output file). Heavy imports happen inside the commands."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console

from vlm_bench.cli.exec_options import ExecBackend, ExecWorkers, RayAddress, execution_options
from vlm_bench.cli.options import parse_seed, parse_variant
from vlm_bench.cli.run_summary import print_run_summary
from vlm_bench.errors import ConfigError

console = Console()


def rescore(
    run_dir: Annotated[
        str, typer.Argument(metavar="RUN", help="Run folder, or a name under results/.")
    ],
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
    exec_workers: ExecWorkers = None,
    exec_backend: ExecBackend = "process",
    ray_address: RayAddress = None,
) -> None:
    """Recompute parses, scores and executions from the response cache (no model calls)."""
    from vlm_bench.api import rescore as api_rescore
    from vlm_bench.resources import results_dir
    from vlm_bench.sim.mujoco_log import route_mujoco_log

    route_mujoco_log()  # rescoring executes plans
    path = Path(run_dir)
    if not path.exists() and (results_dir() / run_dir).exists():
        path = results_dir() / run_dir
    execution = execution_options(exec_workers, exec_backend, ray_address)
    result = api_rescore(path, progress=progress, execution=execution)
    print_run_summary(result)
    console.print(f"{result.stats.changed} record(s) changed", highlight=False)
    if result.stats.torn_bytes:
        console.print(
            f"[yellow]records.jsonl ended in a torn line ({result.stats.torn_bytes} bytes, a "
            "crash mid-write), now cut off: its episode has no record; re-run the run command "
            "to score it again from the response cache[/]",
            soft_wrap=True,
            highlight=False,
        )


def _score_text(data: dict[str, Any]) -> None:
    scores = data["scores"]
    console.print(
        f"[bold]{data['task_id']}[/] seed {data['seed']} · {data['instruction']} · "
        f"parse: {data['parse']['tier']}"
    )
    console.print("plan:    " + json.dumps(data["plan"]), highlight=False, soft_wrap=True)
    console.print("GT plan: " + json.dumps(data["gt_plan"]), highlight=False, soft_wrap=True)
    console.print(
        "  ".join(
            f"{k}={scores[k]:.1f}" for k in ("s_plan", "s_loc", "s_obj", "s_skill", "s_total")
        )
        + f"  succ={scores['succ']}",
        highlight=False,
    )
    console.print("errors: " + (", ".join(data["error_tags"]) or "none"), highlight=False)


def score(
    task: Annotated[str, typer.Argument(help="Task id.")],
    output: Annotated[Path, typer.Option(help="File holding the raw model output.")],
    seed: Annotated[str, typer.Option(help="Episode seed.")] = "0",
    instruction: Annotated[str, typer.Option(help="explicit or implicit.")] = "explicit",
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Score one raw model output file against an episode's GT plan."""
    from vlm_bench.api import score_output

    try:
        text = output.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"cannot read {output}: {exc.strerror}") from None
    data = score_output(task, parse_seed(seed), text, parse_variant(instruction)).model_dump(
        mode="json"
    )
    if as_json:
        typer.echo(json.dumps(data, indent=1))
    else:
        _score_text(data)


def register(app: typer.Typer) -> None:
    """Add ``rescore`` and ``score`` to ``app``."""
    app.command()(rescore)
    app.command()(score)
