"""How a pydantic ValidationError becomes one line: one wording for options and data files."""

from __future__ import annotations

import pytest
from pydantic import BaseModel, ValidationError, field_validator

from vlm_bench.errors import ConfigError, first_problem, option_error


class _Inner(BaseModel):
    size: int


class _Options(BaseModel):
    name: str
    items: list[_Inner] = []

    @field_validator("name")
    @classmethod
    def _short(cls, value: str) -> str:
        if len(value) > 3:
            raise ValueError("at most 3 characters")
        return value


def _error(**data: object) -> ValidationError:
    with pytest.raises(ValidationError) as info:
        _Options.model_validate(data)
    return info.value


def test_first_problem_names_the_field_path_and_counts_the_rest() -> None:
    where, why, more = first_problem(_error(name="ok", items=[{"size": 1}, {"size": "x"}, {}]))
    assert where == "items[1].size"
    assert why.startswith("Input should be a valid integer")
    assert more == 1


def test_a_validators_value_error_reads_without_pydantics_prefix() -> None:
    assert first_problem(_error(name="long")).why == "at most 3 characters"


def test_option_error_is_one_line_naming_what_and_where() -> None:
    err = option_error(_error(name="long"), "run option")
    assert isinstance(err, ConfigError)
    assert str(err) == "invalid run option name: at most 3 characters"


def test_a_problem_of_the_whole_object_is_just_the_reason() -> None:
    with pytest.raises(ValidationError) as info:
        _Options.model_validate("not a mapping")
    err = option_error(info.value, "run option")
    assert str(err).startswith("Input should be")
