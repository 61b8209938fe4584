"""Model cards (``models/*.json``), validated as :class:`~vlm_bench.types.model_card.ModelCard`."""

from __future__ import annotations

from functools import cache

from vlm_bench.catalog.files import load_by_name
from vlm_bench.errors import UnknownNameError
from vlm_bench.resources import models_dir
from vlm_bench.types.model_card import ModelCard
from vlm_bench.types.parse import AnswerFormat


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


@cache
def card_of(model: str) -> ModelCard | None:
    """The card a run's model string names: the card name or hub id, alone or after a backend
    prefix (``glm-4.1v-9b-thinking``, ``vllm/zai-org/GLM-4.1V-9B-Thinking``); None for other
    models."""
    for card in model_cards().values():
        for name in (card.name, card.hub_id):
            if model == name or model.endswith("/" + name):
                return card
    return None


def answer_format_of(model: str) -> AnswerFormat | None:
    """The documented answer format of the card ``model`` names (:func:`card_of`), if any."""
    card = card_of(model)
    return card.answer_format if card is not None else None
