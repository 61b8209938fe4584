"""The task's ``-T`` options, named and parsed as ``vlm-bench run``'s (the CLI's own parsers)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from vlm_bench.cli.options import parse_seeds, parse_suite, perturb_options
from vlm_bench.cli.prompt_options import parse_views
from vlm_bench.cli.run_cmds import parse_instructions
from vlm_bench.errors import ConfigError
from vlm_bench.export.options import ExportOptions, export_options
from vlm_bench.types.closed_loop import LoopMode, PerturbConfig
from vlm_bench.types.run import RunConfig, run_config


@dataclass(frozen=True)
class TaskOptions:
    """What one ``inspect eval vlm_bench/aerial`` evaluates."""

    episodes: ExportOptions
    """Episode selection and prompt options (the dataset export's)."""
    dataset: Path | None
    """An exported dataset folder to read the rows from (None: build them in-process)."""
    loop: LoopMode
    """open: one answer per episode; closed: replan after a failed execution."""
    max_rounds: int
    """Closed loop: replans after round 0 (K)."""
    perturb: PerturbConfig | None
    """Seeded slips and bumps during execution (closed loop)."""
    uav_noise: float
    """Gust force std on the UAV (N) during execution (``perturb`` gust=N)."""


TaskArg = str | int | float | list[str | int | float]
"""A ``-T`` value: inspect's CLI turns ``a,b`` into a list and ``0`` into a number."""


def _text(value: TaskArg) -> str:
    """A ``-T`` value as the CLI's comma-separated text (``seeds=0,3`` → ``"0,3"``)."""
    return ",".join(map(str, value)) if isinstance(value, list) else str(value)


def _tasks(value: TaskArg | None) -> tuple[str, ...]:
    if value is None:
        return ()
    return tuple(p.strip() for p in _text(value).split(",") if p.strip())


def task_options(
    task: TaskArg | None = None,
    suite: str | None = None,
    seeds: TaskArg = "0-9",
    instruction: str = "both",
    views: TaskArg | None = None,
    resolution: int | None = None,
    k_shot: int | None = None,
    loop: str = "open",
    max_rounds: int = 3,
    perturb: TaskArg | None = None,
    dataset: str | None = None,
) -> TaskOptions:
    """Check and parse the ``-T`` options (one-line errors, before any episode is built).

    Raises:
        ConfigError / UnknownNameError: An invalid option, prompt options beside
            ``dataset`` (its rows fix them), or closed-loop options with ``loop=open``.
    """
    if loop not in ("open", "closed"):
        raise ConfigError(f"-T loop must be open or closed, got {loop!r}")
    if loop == "open" and (perturb is not None or max_rounds != 3):
        raise ConfigError("-T max_rounds and perturb need -T loop=closed")
    prompt = {"views": views, "resolution": resolution, "k_shot": k_shot}
    given = {name: value for name, value in prompt.items() if value is not None}
    if dataset is not None and given:
        raise ConfigError(
            f"-T {', '.join(given)}: the dataset's rows fix the prompt options; export the "
            "dataset with them instead"
        )
    fields: dict[str, object] = {
        "tasks": _tasks(task),
        "suite": parse_suite(suite),
        "seeds": tuple(parse_seeds(_text(seeds))),
        "instructions": parse_instructions(instruction),
        **({"views": parse_views(_text(views))} if views is not None else {}),
        **({"resolution": int(resolution)} if resolution is not None else {}),
        **({"k_shot": int(k_shot)} if k_shot is not None else {}),
    }
    perturbations, gust = perturb_options(_text(perturb) if perturb is not None else None, 0.0)
    if dataset is not None and not Path(dataset).is_dir():
        raise ConfigError(f"-T dataset {dataset} is not a dataset folder")
    return TaskOptions(
        episodes=export_options(**fields),
        dataset=Path(dataset) if dataset is not None else None,
        loop="closed" if loop == "closed" else "open",
        max_rounds=int(max_rounds),
        perturb=perturbations,
        uav_noise=gust,
    )


def loop_run_config(options: TaskOptions) -> RunConfig:
    """The run configuration a ``vlm-bench run`` of the same episodes and loop would have
    (its prompts, its closed loop, its executor settings)."""
    fields = options.episodes.run_config().model_dump()
    fields.update(
        model="inspect",
        loop=options.loop,
        uav_noise=options.uav_noise,
        perturb=options.perturb,
        **({"max_rounds": options.max_rounds} if options.loop == "closed" else {}),
    )
    return run_config(**fields)
