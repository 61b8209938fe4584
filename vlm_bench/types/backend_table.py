"""The built-in backends, in one table: the registry, the checks a run makes before it starts
(:mod:`vlm_bench.backends.preflight`), the model cards and the CLI's help all read it.

A new built-in backend is a module under ``vlm_bench/backends/`` and a row here; a backend of
another package is an entry point instead (``vlm_bench.backends``, see docs/design.md).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from vlm_bench.types.base import Frozen

Runs = Literal["weightless", "in_process", "server"]
ModelCheck = Literal["none", "local_or_hub", "local_or_hub_config"]


class BuiltinBackend(Frozen):
    """One built-in backend."""

    name: str = Field(pattern=r"^[a-z][a-z0-9_]*$", description="Registry name.")
    module: str = Field(description="Its module under vlm_bench.backends (imported on use).")
    cls: str = Field(description="Its Backend subclass in that module.")
    prefix: bool = Field(description="Selected by <name>/<model> (else by the bare name).")
    selector: str = Field(description="How a model string selects it, for help texts.")
    description: str = Field(description="One line for `vlm-bench models`.")
    runs: Runs = Field(
        description="weightless: built outright as its own check; in_process: a model loads in "
        "this process; server: a client of a server."
    )
    requires: tuple[str, ...] = Field(default=(), description="Modules its constructor imports.")
    extra: str | None = Field(default=None, description="The pip extra that installs them.")
    constrained_requires: tuple[str, ...] = Field(
        default=(), description="Modules constrained decoding needs besides (extra constrained)."
    )
    model_check: ModelCheck = Field(
        default="none",
        description="What the checks ask of the model name: nothing (a served name), a local "
        "folder or a hub id, or one with a config.json.",
    )
    card: bool = Field(default=False, description="A model card can name it as its backend.")


BUILTIN_BACKENDS: tuple[BuiltinBackend, ...] = (
    BuiltinBackend(
        name="oracle",
        module="builtin",
        cls="OracleBackend",
        prefix=False,
        selector="oracle",
        description="returns the GT plan (ceiling)",
        runs="weightless",
    ),
    BuiltinBackend(
        name="random",
        module="builtin",
        cls="RandomBackend",
        prefix=False,
        selector="random",
        description="seeded random valid plans (floor)",
        runs="weightless",
    ),
    BuiltinBackend(
        name="blind",
        module="blind_planner",
        cls="BlindBackend",
        prefix=False,
        selector="blind",
        description="GT ARM steps, moves guessed (floor)",
        runs="weightless",
    ),
    BuiltinBackend(
        name="rules",
        module="rules_planner",
        cls="RulesBackend",
        prefix=False,
        selector="rules",
        description="plans from --scene-as-text (ceiling)",
        runs="weightless",
    ),
    BuiltinBackend(
        name="mock",
        module="builtin",
        cls="MockBackend",
        prefix=False,
        selector="mock",
        description="scripted outputs (-M file=... or -M text=...)",
        runs="weightless",
    ),
    BuiltinBackend(
        name="openai",
        module="openai_backend",
        cls="OpenAIBackend",
        prefix=True,
        selector="openai/<name>",
        description="OpenAI-compatible server",
        runs="server",
        requires=("openai",),
        extra="openai",
        card=True,
    ),
    BuiltinBackend(
        name="vllm",
        module="vllm_backend",
        cls="VllmBackend",
        prefix=True,
        selector="vllm/<id>",
        description="offline vLLM engine",
        runs="in_process",
        requires=("vllm",),
        extra="vllm",
        model_check="local_or_hub",
        card=True,
    ),
    BuiltinBackend(
        name="hf",
        module="hf",
        cls="HfBackend",
        prefix=False,
        selector="HF id/path",
        description="transformers image-text-to-text (HF id or path)",
        runs="in_process",
        requires=("torch", "transformers"),
        extra="hf",
        constrained_requires=("xgrammar",),
        model_check="local_or_hub_config",
        card=True,
    ),
)


def card_backends() -> tuple[str, ...]:
    """The backends a model card can name."""
    return tuple(b.name for b in BUILTIN_BACKENDS if b.card)


def model_string_help() -> str:
    """What ``--model`` takes, from the table (the CLI's help)."""
    order = sorted(BUILTIN_BACKENDS, key=lambda b: (b.runs == "weightless", b.prefix))
    return ", ".join(b.selector for b in order) + ", a model card, or <plug-in>/<model>."
