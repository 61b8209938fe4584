"""Model cards (``models/*.json``), validated as :class:`~vlm_bench.types.model_card.ModelCard`."""

from __future__ import annotations

from functools import cache

from vlm_bench.catalog.files import load_by_name
from vlm_bench.errors import UnknownNameError
from vlm_bench.resources import models_dir
from vlm_bench.types.model_card import ModelCard


@cache
def model_cards() -> dict[str, ModelCard]:
    """Every card by name, in file-name order (cached)."""
    return load_by_name(models_dir(), ModelCard, lambda card: card.name)


def model_card(name: str) -> ModelCard:
    """One card by name; raises listing the cards."""
    cards = model_cards()
    if name not in cards:
        raise UnknownNameError("model card", name, cards)
    return cards[name]
