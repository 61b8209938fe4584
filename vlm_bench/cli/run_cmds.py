"""Planning commands: run, rescore, score (``execute`` lives in :mod:`.execute_cmd`). Heavy
imports happen inside the commands."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import typer
from rich.console import Console

from vlm_bench.cli.exit_codes import EXIT_CODES_HELP, ExitCode
from vlm_bench.cli.options import (
    finite,
    parse_seed,
    parse_seeds,
    parse_suite,
    parse_variant,
    perturb_options,
    table_console,
)
from vlm_bench.cli.prompt_options import (
    DEFAULT_BATCH_SIZE,
    DEFAULT_K_SHOT,
    DEFAULT_MAX_NEW_TOKENS,
    DEFAULT_RESOLUTION,
    DEFAULT_TEMPERATURE,
    DEFAULT_VIEWS,
    KShotOption,
    NoImagesOption,
    NoObjectListOption,
    NoSnapshotCacheOption,
    ResolutionOption,
    SceneAsTextOption,
    ViewsOption,
    prompt_fields,
    run_default,
)
from vlm_bench.cli.protocol_option import ProtocolOption, apply_protocol, protocol_line
from vlm_bench.errors import ConfigError, option_error

if TYPE_CHECKING:
    from vlm_bench.api import RunResult
    from vlm_bench.types.execution import ExecutionOptions
    from vlm_bench.types.task import InstructionVariant

console = Console()
ExecWorkers = Annotated[
    int | None,
    typer.Option(
        min=0,
        help="Plans executed at once (default: the machine's cores; 0 = one by one in this "
        "process).",
    ),
]
ExecBackend = Annotated[
    str, typer.Option(help="Where plans are executed: process (this machine) or ray.")
]
RayAddress = Annotated[
    str | None,
    typer.Option(help="Ray cluster to execute on (--exec-backend ray; default: a local one)."),
]
ExecStall = Annotated[
    float | None,
    typer.Option(
        min=0.001,
        help="Give up the executions in flight when none finishes for this long (s; default 900): "
        "a hung worker or a lost node; a resume runs them again.",
    ),
]


def execution_options(
    workers: int | None, backend: str, address: str | None, stall_s: float | None = None
) -> ExecutionOptions:
    """``--exec-workers/--exec-backend/--ray-address/--exec-stall-s`` checked (before anything
    is written)."""
    import importlib.util

    from vlm_bench.types.execution import ExecutionOptions

    if backend not in ("process", "ray"):
        raise ConfigError(f"unknown --exec-backend {backend!r}; use process or ray")
    if address is not None and backend != "ray":
        raise ConfigError("--ray-address needs --exec-backend ray")
    if backend == "ray" and importlib.util.find_spec("ray") is None:
        raise ConfigError("--exec-backend ray needs Ray: pip install -e '.[ray]'")
    if backend == "ray":
        from vlm_bench.runner.executions_ray import check_ray_address

        check_ray_address(address)
    kind: Literal["process", "ray"] = "ray" if backend == "ray" else "process"
    options = ExecutionOptions(workers=workers, backend=kind, ray_address=address)
    if stall_s is None:
        return options
    return options.model_copy(update={"stall_s": finite("--exec-stall-s", stall_s)})


def sampling_settings(model: str, temperature: float) -> dict[str, float | int]:
    """The decoding settings of ``--sampling``: the model card's ``sampling`` preset.

    Raises:
        ConfigError: No card for the model, a card without a preset, or --temperature too.
    """
    from vlm_bench.catalog.model_cards import card_of

    if temperature != 0.0:
        raise ConfigError("give --sampling or --temperature, not both")
    card = card_of(model)
    if card is None or card.sampling is None:
        what = "no model card" if card is None else f"card {card.name} has no sampling preset"
        raise ConfigError(f"--sampling needs a model card's preset: {model!r} has {what}")
    return card.sampling.model_dump(exclude={"source"})


def parse_instructions(text: str) -> tuple[InstructionVariant, ...]:
    """``explicit``, ``implicit`` or ``both``."""
    if text.strip().lower() == "both":
        return ("explicit", "implicit")
    return (parse_variant(text),)


def _print_summary(result: RunResult) -> None:
    from vlm_bench.report import summary_rich
    from vlm_bench.types.execution import FailureCode
    from vlm_bench.types.protocol_match import manifest_protocol

    # Piped: no terminal width to respect, so the table is not wrapped or cut.
    shown = table_console(console)
    shown.print(summary_rich(result.summary, title=result.run_id, width=shown.width))
    stats = result.stats
    line = f"{result.run_dir}: summary.md, summary.csv, records.jsonl ({stats.total} episodes"
    if stats.skipped:
        line += f", {stats.skipped} resumed"
    if stats.cached:
        line += f", {stats.cached} from the response cache"
    if stats.executed:
        line += f", {stats.executed} plan(s) executed"
    console.print(line + ")", highlight=False, soft_wrap=True)
    console.print(protocol_line(manifest_protocol(result.manifest)), highlight=False)
    unanswered = [r for r in result.records if not r.ok]
    if unanswered:
        first = unanswered[0]
        console.print(
            f"[yellow]{len(unanswered)} of {len(result.records)} episode(s) have no result "
            f"(the backend failed after its retries, or an execution was lost; e.g. {first.key}: "
            f"{first.backend_error}); re-run the same command to retry them[/]",
            soft_wrap=True,
            highlight=False,
        )
    crashed = [
        (r.key, r.execution.failure_reason)
        for r in result.records
        if r.execution is not None and r.execution.failure_code is FailureCode.EXECUTOR_CRASH
    ]
    if crashed:
        key, reason = crashed[0]
        console.print(
            f"[yellow]{len(crashed)} execution(s) raised in the executor (recorded as "
            f"failures), e.g. {key}: {reason}[/]",
            soft_wrap=True,
            highlight=False,
        )


def run(
    ctx: typer.Context,
    model: Annotated[
        str,
        typer.Option(
            help="HF id/path, openai/<name>, vllm/<id>, oracle, random, blind, rules, mock."
        ),
    ],
    task: Annotated[list[str] | None, typer.Option(help="Task id (repeatable).")] = None,
    suite: Annotated[str | None, typer.Option(help="Only this suite (e.g. lh).")] = None,
    seeds: Annotated[str, typer.Option(help="Seeds: 0-9 or 0,3,5.")] = "0",
    instruction: Annotated[str, typer.Option(help="explicit, implicit or both.")] = "both",
    views: ViewsOption = DEFAULT_VIEWS,
    resolution: ResolutionOption = DEFAULT_RESOLUTION,
    k_shot: KShotOption = DEFAULT_K_SHOT,
    no_object_list: NoObjectListOption = False,
    no_images: NoImagesOption = False,
    scene_as_text: SceneAsTextOption = False,
    constrained: Annotated[bool, typer.Option(help="JSON-schema constrained decoding.")] = False,
    model_arg: Annotated[
        list[str] | None,
        typer.Option("--model-arg", "-M", help="Backend argument key=value (repeatable)."),
    ] = None,
    batch_size: Annotated[
        int, typer.Option(help="Requests per generate call.")
    ] = DEFAULT_BATCH_SIZE,
    max_new_tokens: Annotated[
        int, typer.Option(help="Most tokens generated.")
    ] = DEFAULT_MAX_NEW_TOKENS,
    temperature: Annotated[float, typer.Option(help="0 = greedy.")] = DEFAULT_TEMPERATURE,
    sampling: Annotated[
        bool,
        typer.Option(
            "--sampling", help="Decode with the model card's recommended sampling (not greedy)."
        ),
    ] = False,
    run_name: Annotated[str | None, typer.Option(help="Folder name under results/.")] = None,
    out: Annotated[Path | None, typer.Option(help="Run folder (instead of --run-name).")] = None,
    no_snapshot_cache: NoSnapshotCacheOption = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
    execute: Annotated[
        bool,
        typer.Option("--execute/--no-execute", help="Execute every valid plan in the simulator."),
    ] = run_default("execute"),
    uav_noise: Annotated[
        float,
        typer.Option(
            help="Gust force std on the UAV in N during execution (the paper's UAV Disturb.)."
        ),
    ] = run_default("uav_noise"),
    loop: Annotated[
        str,
        typer.Option(help="open: one plan per episode; closed: replan after a failed round."),
    ] = run_default("loop"),
    max_rounds: Annotated[
        int, typer.Option(help="Closed loop: replans after round 0 (K).")
    ] = run_default("max_rounds"),
    step_budget: Annotated[
        int | None,
        typer.Option(help="Closed loop: steps over all rounds (default 3 x the GT plan's)."),
    ] = None,
    history: Annotated[
        str,
        typer.Option(
            help="Closed loop, multi-turn backends: earlier rounds as text (only the current "
            "views as images) or with their views (images)."
        ),
    ] = run_default("history"),
    perturb: Annotated[
        str | None,
        typer.Option(
            help="Seeded perturbations slip=P,bump=P,gust=N (gust = --uav-noise), in open "
            "and closed loop alike."
        ),
    ] = None,
    exec_workers: ExecWorkers = None,
    exec_backend: ExecBackend = "process",
    ray_address: RayAddress = None,
    exec_stall_s: ExecStall = None,
    protocol: ProtocolOption = None,
) -> None:
    """Evaluate a model as a planner (and execute its plans); resumes the run folder."""
    from pydantic import ValidationError

    from vlm_bench.api import run as api_run
    from vlm_bench.api import run_dir_for
    from vlm_bench.backends import parse_model_args
    from vlm_bench.types.generation import GenerationConfig
    from vlm_bench.types.run import run_config

    finite("--temperature", temperature)
    finite("--uav-noise", uav_noise)
    decoding = sampling_settings(model, temperature) if sampling else {"temperature": temperature}
    perturbations, uav_noise = perturb_options(perturb, uav_noise)
    try:
        generation = GenerationConfig(
            max_new_tokens=max_new_tokens,
            constrained=constrained,
            batch_size=batch_size,
            **decoding,
        )
    except ValidationError as exc:
        raise option_error(exc, "option") from None
    config = run_config(
        model=model,
        backend_args=parse_model_args(model_arg or []),
        tasks=tuple(task or ()),
        suite=parse_suite(suite),
        seeds=tuple(parse_seeds(seeds)),
        instructions=parse_instructions(instruction),
        **prompt_fields(views, resolution, k_shot, no_object_list, no_images, scene_as_text),
        generation=generation,
        execute=execute,
        uav_noise=uav_noise,
        loop=loop,
        max_rounds=max_rounds,
        step_budget=step_budget,
        history=history,
        perturb=perturbations,
    )
    config = apply_protocol(config, protocol, ctx)
    execution = execution_options(exec_workers, exec_backend, ray_address, exec_stall_s)
    run_dir = run_dir_for(config, out, run_name)
    try:
        result = api_run(
            config,
            out=run_dir,
            snapshot_cache=not no_snapshot_cache,
            progress=progress,
            execution=execution,
        )
    except KeyboardInterrupt as exc:
        from vlm_bench.runner.interrupt import Terminated

        terminated = isinstance(exc, Terminated)
        print(
            f"{'terminated' if terminated else 'interrupted'}: finished episodes are saved in "
            f"{run_dir}; re-run the same command to resume",
            file=sys.stderr,
        )
        code = ExitCode.TERMINATED if terminated else ExitCode.INTERRUPTED
        raise typer.Exit(code) from None
    _print_summary(result)
    if any(not r.ok for r in result.records):
        raise typer.Exit(ExitCode.UNANSWERED)


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
    _print_summary(result)
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
    """Add the planning commands to ``app``."""
    app.command(epilog=EXIT_CODES_HELP)(run)
    app.command()(rescore)
    app.command()(score)
