"""``vlm-bench models``: the backends and the model cards, or one card's recipe. Imports no
backend dependency (torch, transformers, vllm, openai)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Annotated

import typer
from rich.console import Console
from rich.table import Table

from vlm_bench.cli.options import table_console

if TYPE_CHECKING:
    from vlm_bench.types.model_card import ModelCard

console = Console()


def _listing() -> None:
    from vlm_bench.backends import BACKENDS, load_plugins
    from vlm_bench.catalog.model_cards import model_cards

    load_plugins()
    backends = Table(title="Backends", title_justify="left")
    for column in ("backend", "model string", "what"):
        backends.add_column(column)
    for name in BACKENDS.names():  # the built-ins' table, then the plug-ins
        entry = BACKENDS.get(name)
        if entry.builtin is not None:
            selector = entry.builtin.selector
        else:
            selector = name + ("/<model>" if entry.takes_model else "")
        backends.add_row(name, selector, entry.description)
    cards = Table(
        title="Model cards (--model <card>; vlm-bench models <card>)", title_justify="left"
    )
    cards.add_column("card", no_wrap=True)  # an id to copy: never cut
    for column in ("model", "checkpoint", "backend", "paper"):
        cards.add_column(column, overflow="fold")
    for card in model_cards().values():
        cards.add_row(
            card.name, card.title, card.hub_id, card.backend, "yes" if card.in_paper else "no"
        )
    shown = table_console(console)  # piped: as wide as the rows, nothing cut
    shown.print(backends)
    shown.print(cards)


def _sampling(card: ModelCard) -> str:
    preset = card.sampling
    if preset is None:
        return "no preset"
    if preset.temperature == 0 and preset.repetition_penalty == 1.0:
        return f"greedy, as the authors decode ({preset.source})"
    settings = preset.model_dump(exclude={"source"})
    text = ", ".join(f"{k} {v}" for k, v in settings.items())
    return f"{text} with --sampling ({preset.source})"


def _recipe(name: str, as_json: bool) -> None:
    from vlm_bench.backends.recipes import recipe_lines
    from vlm_bench.catalog.model_cards import model_card

    card = model_card(name)
    lines = recipe_lines(card)
    budget = card.token_budget()
    if as_json:
        data = {
            **card.model_dump(mode="json"),
            "tokens_per_view": budget.model_dump(mode="json"),
            "commands": lines,
        }
        typer.echo(json.dumps(data, indent=1))
        return
    console.print(f"[bold]{card.title}[/] ({card.name}) · {card.hub_id}", highlight=False)
    facts = [
        ("architecture", card.architecture),
        ("backend", f"{card.backend} (--model {card.name})"),
        ("dtype", card.dtype),
        ("remote code", "yes" if card.remote_code else "no"),
        ("images", card.images),
        (
            "image tokens",
            f"{budget.four_views} per {budget.resolution} px view of four, {budget.one_view} "
            f"for one alone; the recipe's {budget.recipe_views} view(s): "
            f"{budget.recipe_image_tokens}",
        ),
        ("decoding", f"greedy, max_new_tokens {card.max_new_tokens}"),
        ("sampling", _sampling(card)),
        ("in the paper", "yes" if card.in_paper else "no (a stand-in)"),
    ]
    facts += [(f"no {backend}", why) for backend, why in card.unsupported.items()]
    for label, text in facts:
        console.print(f"  {label + ':':14} {text}", highlight=False, soft_wrap=True)
    for label, line in lines.items():
        console.print(f"  {label + ':':14} {line}", highlight=False, soft_wrap=True, markup=False)
    for quirk in card.quirks:
        console.print(f"  - {quirk}", highlight=False, soft_wrap=True, markup=False)


def models(
    card: Annotated[
        str | None, typer.Argument(help="A model card's name: print its recipe.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print the card as JSON.")] = False,
) -> None:
    """List the backends and model cards, or print one card's recipe (exact command lines)."""
    if card is None:
        _listing()
    else:
        _recipe(card, as_json)


def register(app: typer.Typer) -> None:
    """Add ``models`` to ``app``."""
    app.command()(models)
