"""The ``run`` command (``rescore`` and ``score``: :mod:`.score_cmds`; ``execute``:
:mod:`.execute_cmd`). Heavy imports happen inside the commands."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from vlm_bench.cli import score_cmds
from vlm_bench.cli.exec_options import (
    ExecBackend,
    ExecStall,
    ExecWorkers,
    RayAddress,
    execution_options,
)
from vlm_bench.cli.exit_codes import EXIT_CODES_HELP, ExitCode
from vlm_bench.cli.options import (
    finite,
    parse_seeds,
    parse_suite,
    parse_variant,
    perturb_options,
)
from vlm_bench.cli.prompt_options import (
    DEFAULT_BATCH_SIZE,
    DEFAULT_K_SHOT,
    DEFAULT_MAX_NEW_TOKENS,
    DEFAULT_RESOLUTION,
    DEFAULT_TEMPERATURE,
    DEFAULT_VIEWS,
    InstructionOption,
    KShotOption,
    NoImagesOption,
    NoObjectListOption,
    NoSnapshotCacheOption,
    ResolutionOption,
    SceneAsTextOption,
    SuiteOption,
    TaskOption,
    ViewsOption,
    prompt_fields,
    run_default,
)
from vlm_bench.cli.protocol_option import ProtocolOption, apply_protocol
from vlm_bench.cli.run_summary import print_run_summary
from vlm_bench.errors import ConfigError, option_error

if TYPE_CHECKING:
    from vlm_bench.types.task import InstructionVariant


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


def run(
    ctx: typer.Context,
    model: Annotated[
        str,
        typer.Option(
            help="HF id/path, openai/<name>, vllm/<id>, oracle, random, blind, rules, mock."
        ),
    ],
    task: TaskOption = None,
    suite: SuiteOption = None,
    seeds: Annotated[str, typer.Option(help="Seeds: 0-9 or 0,3,5.")] = "0",
    instruction: InstructionOption = "both",
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
    print_run_summary(result)
    if any(not r.ok for r in result.records):
        raise typer.Exit(ExitCode.UNANSWERED)


def register(app: typer.Typer) -> None:
    """Add the planning commands (run, rescore, score) to ``app``."""
    app.command(epilog=EXIT_CODES_HELP)(run)
    score_cmds.register(app)
