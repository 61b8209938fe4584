"""The one table of built-in backends: the registry, the run's checks, the cards and the help
read it, so a row is all a built-in needs besides its module."""

from __future__ import annotations

import pytest

from vlm_bench.backends import BACKENDS, Backend
from vlm_bench.backends.backend_registry import builtin_class
from vlm_bench.backends.preflight import check_backend
from vlm_bench.catalog.model_cards import model_cards
from vlm_bench.types.backend_table import (
    BUILTIN_BACKENDS,
    BuiltinBackend,
    card_backends,
    model_string_help,
)
from vlm_bench.types.model_card import ModelCard


@pytest.mark.parametrize("row", BUILTIN_BACKENDS, ids=lambda row: row.name)
def test_each_row_is_a_registered_backend_class(row: BuiltinBackend) -> None:
    cls = builtin_class(row)
    assert issubclass(cls, Backend) and cls.name == row.name
    entry = BACKENDS.get(row.name)
    assert entry.builtin == row and entry.takes_model == row.prefix
    assert row.selector in model_string_help()


def test_weightless_rows_are_checked_by_building_them() -> None:
    for row in BUILTIN_BACKENDS:
        if row.runs == "weightless" and row.name != "mock":
            assert check_backend(row.name).name == row.name


def test_cards_name_only_card_backends() -> None:
    assert set(card_backends()) == {"hf", "vllm", "openai"}
    assert {card.backend for card in model_cards().values()} <= set(card_backends())
    data = next(iter(model_cards().values())).model_dump()
    with pytest.raises(ValueError, match="not a backend a card can name"):
        ModelCard.model_validate({**data, "backend": "oracle"})
