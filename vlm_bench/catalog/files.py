"""Read JSON data files into pydantic models, turning any failure into a one-line error."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

from pydantic import BaseModel, ValidationError

from vlm_bench.errors import DataFileError, first_problem

M = TypeVar("M", bound=BaseModel)


def not_utf8(exc: UnicodeDecodeError) -> str:
    """What is wrong with a file that is not UTF-8 text, and where."""
    return f"not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at offset {exc.start})"


def read_json(path: Path) -> object:
    """Parse a JSON file; raises :class:`DataFileError` naming the file on failure."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise DataFileError(str(path), f"cannot read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise DataFileError(str(path), not_utf8(exc)) from None
    except json.JSONDecodeError as exc:
        raise DataFileError(str(path), f"invalid JSON at line {exc.lineno}: {exc.msg}") from None


def load_model(path: Path, model: type[M]) -> M:
    """Validate a JSON file against ``model``; the error names the file and the first bad field."""
    data = read_json(path)
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        where, why, more = first_problem(exc)
        extra = f" (+{more} more)" if more else ""
        raise DataFileError(str(path), f"{where or '(root)'}: {why}{extra}") from None


def load_by_name(folder: Path, model: type[M], name: Callable[[M], str]) -> dict[str, M]:
    """Every ``*.json`` in ``folder`` validated against ``model``, by ``name``, in file-name
    order; a file whose ``name`` differs from its file name is an error."""
    out: dict[str, M] = {}
    for path in sorted(folder.glob("*.json")):
        item = load_model(path, model)
        if name(item) != path.stem:
            raise DataFileError(str(path), f"name: {name(item)!r} differs from the file name")
        out[name(item)] = item
    return out
