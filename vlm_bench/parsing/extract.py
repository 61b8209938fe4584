"""Deterministic repair: from raw model text to the JSON values that may hold a plan.

Order: strip reasoning blocks, take the last code fence that holds JSON
(:mod:`~vlm_bench.parsing.wrappers`), then collect the candidate values of the remaining text
(:func:`candidates`):

* every strict JSON array/object that starts at a ``[`` or ``{`` anywhere in the text, decoded
  with :meth:`json.JSONDecoder.raw_decode` (so a stray bracket in the prose before the plan
  cannot hide it);
* every bracketed region that is not strict JSON, found by a lenient, string-aware bracket
  matcher (:mod:`~vlm_bench.parsing.brackets`: the outermost closed regions, also inside a
  region still open at the end, and that region), loaded with json-repair (a closed region too
  long for it: as a Python literal).

The work is bounded so that parsing stays linear in the length of the output (the ``MAX_``
constants below); outputs of ordinary size (under 20 kB) never reach the bounds.
"""

from __future__ import annotations

import ast
import json
import math
import re
import warnings
from bisect import bisect_right
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import Any

import json_repair

from vlm_bench.parsing.brackets import Span, scan_spans
from vlm_bench.types.parse import Repair

MAX_REPAIRS = 64  # json-repair runs on at most this many spans (the last ones) per text
MAX_REPAIR_CHARS = 100_000  # ... and is handed at most this many characters in all per text
MAX_LITERAL_CHARS = 2_000_000  # longer closed spans: loaded as Python literals, this many chars
MAX_DEPTH = 32  # plans are 2–3 levels deep; deeper spans are not parsed (recursion limits)
_DECODE_BUDGET = 4  # failed strict decodes read at most this many times the text (+ 64 kB)
_ATTEMPT_COST = 32  # what one failed decode costs beyond the characters it read
_WINDOW = 256  # strict decoding reads a window this long first, then 4x longer ones
_CUT_MARGIN = 16  # a decode error this close to the window's end may be the cut, not the JSON

# Python strings (single- or double-quoted, one line), constants and trailing commas, for
# :func:`_literal`.
_PY_TOKEN = re.compile(
    r"""'((?:[^'\\\n]|\\.)*)'|"((?:[^"\\\n]|\\.)*)"|\b(True|False|None)\b|,(?=\s*[\]}])"""
)
_PY_KEYWORDS = {"True": "true", "False": "false", "None": "null"}
# Where a strict JSON array/object can start: the bracket, then what may follow it in JSON.
_JSON_START = re.compile(r"""\[(?=\s*[\[{"\]\-0-9tfnNI])|\{(?=\s*["}])""")


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def json_int(digits: str) -> int | float:
    """A JSON integer; one too long for ``int`` (Python's 4,300-digit limit) loads as ±inf,
    which no plan field accepts (so it is recorded as a bad value, not raised)."""
    try:
        return int(digits)
    except ValueError:
        return -math.inf if digits.startswith("-") else math.inf


def strict_loads(text: str) -> tuple[Any, bool]:
    """``json.loads`` that rejects NaN/Infinity and deep nesting; returns (value, ok)."""
    try:
        return json.loads(text, parse_constant=_reject_constant, parse_int=json_int), True
    except (ValueError, RecursionError):
        return None, False


def _depth(value: Any, limit: int) -> int:
    """Nesting depth of lists/dicts in ``value`` (1 for a flat list), counted up to limit + 1."""
    deepest = 0
    todo = [(value, 1)]
    while todo:
        item, depth = todo.pop()
        deepest = max(deepest, depth)
        if depth > limit:
            break
        children = item.values() if isinstance(item, dict) else item
        todo.extend((c, depth + 1) for c in children if isinstance(c, list | dict))
    return deepest


def _strict_values(text: str) -> Iterator[tuple[Any, Span]]:
    """Strict JSON arrays/objects of ``text``, in text order, none inside another.

    Each ``[``/``{`` that can start JSON is tried with ``raw_decode`` on a window of the text
    that grows while the error may come from the cut (the error object costs a pass over the
    text before the error, so the whole text is never handed over from each bracket). The
    characters read by failed attempts are bounded by :data:`_DECODE_BUDGET` times the text.
    """
    constants: list[str] = []

    def parse_constant(name: str) -> float:
        constants.append(name)  # NaN/Infinity: not JSON; such a value is rejected
        return 0.0

    decoder = json.JSONDecoder(parse_constant=parse_constant, parse_int=json_int)
    budget = _DECODE_BUDGET * len(text) + 65_536
    n = len(text)
    match = _JSON_START.search(text)
    while match is not None and budget > 0:
        start, size = match.start(), _WINDOW
        value, end = None, -1
        while True:
            window = text[start : start + size]
            constants.clear()
            try:
                value, end = decoder.raw_decode(window)
                if constants:  # NaN/Infinity inside: rejected
                    budget -= end + _ATTEMPT_COST
                break
            except json.JSONDecodeError as err:
                budget -= err.pos + _ATTEMPT_COST
                cut = start + size < n and (
                    err.pos >= len(window) - _CUT_MARGIN or err.msg.startswith("Unterminated")
                )
                if not cut:
                    break
                size *= 4
            except (ValueError, RecursionError):  # too deep, or a value Python cannot hold
                budget -= len(window) + _ATTEMPT_COST
                break
        if end < 0 or constants:
            match = _JSON_START.search(text, start + 1)
            continue
        depth = _depth(value, MAX_DEPTH)
        if depth <= MAX_DEPTH:  # deeper values are not parsed (as for spans)
            yield value, Span(start, start + end, True, depth)
        match = _JSON_START.search(text, start + end)


def _as_json(value: Any) -> Any:
    """A Python literal as JSON data (tuples → lists); raises ValueError for other types."""
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, list | tuple):
        return [_as_json(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _as_json(v) for k, v in value.items()}
    raise ValueError(f"{type(value).__name__} is not JSON")


def _repair(text: str) -> Any:
    try:
        repaired = json_repair.loads(text)
    # json-repair applies open-ended heuristics to arbitrary text; any failure means "no JSON".
    except Exception:  # noqa: BLE001
        return None
    if isinstance(repaired, tuple):  # only with logging=True, which is not used
        repaired = repaired[0]
    return None if repaired == "" else repaired


def _python_string(match: re.Match[str]) -> str:
    if match.group(0) == ",":  # trailing comma
        return ""
    keyword = match.group(3)
    if keyword is not None:
        return _PY_KEYWORDS[keyword]
    body = match.group(1) if match.group(1) is not None else match.group(2)
    if "\\" in body or '"' in body:
        return json.dumps(ast.literal_eval(match.group(0)))
    return f'"{body}"'


def _literal(text: str) -> Any:
    """``text`` as a Python literal, or None.

    Quick path: Python strings, ``True``/``False``/``None`` and trailing commas are rewritten
    as JSON and the result is loaded with ``json`` (a long ``repr`` of a plan loads in a tenth
    of a second per MB); when that fails, ``ast.literal_eval``.
    """
    try:
        with warnings.catch_warnings():  # e.g. invalid escape sequences in the model's strings
            warnings.simplefilter("ignore")
            try:
                rewritten = _PY_TOKEN.sub(_python_string, text)
                return json.loads(
                    rewritten, parse_constant=_reject_constant, parse_int=json_int, strict=False
                )
            except (ValueError, SyntaxError, RecursionError):
                return _as_json(ast.literal_eval(text))
    # Syntax, value, memory and recursion errors alike mean "not a Python literal".
    except Exception:  # noqa: BLE001
        return None


@dataclass(frozen=True)
class Candidate:
    """A JSON value loaded from one span of the text."""

    value: Any
    span: Span
    repairs: tuple[Repair, ...]


def _mark_nested(cands: list[Candidate]) -> list[Candidate]:
    """Sort by position (outer first) and flag the candidates inside another's span."""
    cands.sort(key=lambda c: (c.span.start, -c.span.end))
    out: list[Candidate] = []
    end = -1
    for c in cands:
        inside = c.span.end <= end
        end = max(end, c.span.end)
        out.append(replace(c, span=replace(c.span, nested=True)) if inside else c)
    return out


def candidates(text: str) -> tuple[list[Candidate], int | None]:
    """The candidate values of ``text`` in text order, and where the last bracket still open at
    the end of the text opened (None when there is none; see :func:`scan_spans`).

    Strict JSON values come first (see :func:`_strict_values`); the bracketed regions that are
    not strict JSON and lie outside them are then loaded, the last ones first: json-repair runs
    on at most :data:`MAX_REPAIRS` of them and :data:`MAX_REPAIR_CHARS` characters in all, and a
    closed region too long for that is loaded as a Python literal (the common ``repr`` of a long
    plan) up to :data:`MAX_LITERAL_CHARS` characters in all.
    """
    stripped = text.strip()

    def candidate(value: Any, span: Span, repaired: bool) -> Candidate:
        chunk = text[span.start : span.end]
        repairs = (Repair.EXTRACT,) if chunk.strip() != stripped else ()
        return Candidate(value, span, repairs + ((Repair.JSON_REPAIR,) if repaired else ()))

    out = [candidate(value, span, False) for value, span in _strict_values(text)]
    starts, ends = [c.span.start for c in out], [c.span.end for c in out]
    spans, last_open = scan_spans(text)
    repairs, chars, literal_chars = MAX_REPAIRS, MAX_REPAIR_CHARS, MAX_LITERAL_CHARS
    for span in reversed(spans):
        k = bisect_right(starts, span.start) - 1
        if span.depth > MAX_DEPTH or (k >= 0 and ends[k] >= span.end):
            continue  # too deep, or inside a strict value (or that value itself)
        chunk = text[span.start : span.end]
        value, ok = strict_loads(chunk)
        if ok:
            out.append(candidate(value, span, False))
            continue
        if repairs <= 0 or "{" not in chunk or ":" not in chunk:
            continue
        if len(chunk) <= chars:
            repairs, chars = repairs - 1, chars - len(chunk)
            value = _repair(chunk)
        elif span.closed and len(chunk) <= literal_chars:
            literal_chars -= len(chunk)
            value = _literal(chunk)
        else:
            continue
        if value is not None:
            out.append(candidate(value, span, True))
    return _mark_nested(out), last_open
