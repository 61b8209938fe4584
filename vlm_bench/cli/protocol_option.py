"""``--protocol paper|closed|custom`` of ``vlm-bench run``: the option, the options the user
gave (click's parameter sources), and the line that says which protocol a run is."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

import typer

if TYPE_CHECKING:
    from vlm_bench.types.protocol import ProtocolMark
    from vlm_bench.types.run import RunConfig

ProtocolOption = Annotated[
    str | None,
    typer.Option(
        help="A stated protocol: paper (seeds 0-9, both instructions, four views at 448 px, "
        "2-shot, greedy, open loop; the one to quote), closed (paper + --loop closed "
        "--max-rounds 3 --perturb slip=0.3,bump=0.3) or custom. Unset options take the "
        "protocol's values; --task/--suite/--seeds/--instruction may narrow its episodes.",
    ),
]

CLI_FIELDS = {
    "task": "tasks",
    "suite": "suite",
    "seeds": "seeds",
    "instruction": "instructions",
    "views": "views",
    "resolution": "resolution",
    "k_shot": "k_shot",
    "no_object_list": "object_list",
    "no_images": "images",
    "scene_as_text": "scene_as_text",
    "constrained": "generation",
    "temperature": "generation",
    "sampling": "generation",
    "execute": "execute",
    "uav_noise": "uav_noise",
    "loop": "loop",
    "max_rounds": "max_rounds",
    "step_budget": "step_budget",
    "history": "history",
    "perturb": "perturb",
}
"""``vlm-bench run`` parameters → the RunConfig fields they set."""


def given_fields(context: typer.Context) -> set[str]:
    """The RunConfig fields whose options the command line (or environment) set."""
    given = {
        field
        for param, field in CLI_FIELDS.items()
        if getattr(context.get_parameter_source(param), "name", "")
        in ("COMMANDLINE", "ENVIRONMENT")
    }
    if "perturb" in given:
        given.add("uav_noise")  # --perturb gust=N sets it
    return given


def apply_protocol(config: RunConfig, name: str | None, context: typer.Context) -> RunConfig:
    """``config`` under ``--protocol`` (unchanged without it); see
    :func:`vlm_bench.types.protocol_match.with_protocol`."""
    from vlm_bench.types.protocol_match import with_protocol

    return with_protocol(config, name, given_fields(context))


def protocol_line(mark: ProtocolMark) -> str:
    """What a run prints about its protocol: which one, and the share of it the run ran."""
    from vlm_bench.types.protocol import CUSTOM, QUOTED

    if mark.name == CUSTOM:
        return (
            "protocol: custom (settings differ from every stated protocol; "
            f"--protocol {QUOTED} gives the one a paper quotes)"
        )
    if mark.complete:
        return f"protocol: {mark.name} (all {mark.protocol_episodes:,} episodes)"
    return f"protocol: {mark.label()}"
