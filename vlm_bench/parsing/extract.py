"""Deterministic repair: from raw model text to the JSON values that may hold a plan.

Order: strip reasoning blocks, take the last code fence that holds JSON, then collect the
candidate values of the remaining text (:func:`candidates`):

* every strict JSON array/object that starts at a ``[`` or ``{`` anywhere in the text, decoded
  with :meth:`json.JSONDecoder.raw_decode` (so a stray bracket in the prose before the plan
  cannot hide it);
* every bracketed region that is not strict JSON, found by a lenient, string-aware bracket
  matcher (the outermost closed regions, also inside a region still open at the end, and that
  region), loaded with json-repair (a closed region too long for it: as a Python literal).

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

from vlm_bench.types.parse import Repair

MAX_REPAIRS = 64  # json-repair runs on at most this many spans (the last ones) per text
MAX_REPAIR_CHARS = 100_000  # ... and is handed at most this many characters in all per text
MAX_LITERAL_CHARS = 2_000_000  # longer closed spans: loaded as Python literals, this many chars
MAX_DEPTH = 32  # plans are 2–3 levels deep; deeper spans are not parsed (recursion limits)
MAX_RESCANS = 4  # how many times a region still open at the end is re-scanned for regions inside it
MAX_RESCAN_CHARS = 200_000  # ... reading at most this many characters in all
_DECODE_BUDGET = 4  # failed strict decodes read at most this many times the text (+ 64 kB)
_ATTEMPT_COST = 32  # what one failed decode costs beyond the characters it read
_WINDOW = 256  # strict decoding reads a window this long first, then 4x longer ones
_CUT_MARGIN = 16  # a decode error this close to the window's end may be the cut, not the JSON

_THINK_TAG = re.compile(r"<(/?)(think|thinking|reasoning)\s*>", re.I)
_THINK_CLOSE = re.compile(r"</(?:think|thinking|reasoning)\s*>", re.I)
_THINK_OPEN = re.compile(r"<(?:think|thinking|reasoning)\s*>", re.I)
_FENCE = re.compile(r"```[A-Za-z0-9_+-]*[ \t]*\n?(.*?)(?:```|\Z)", re.S)
_OPEN = {"[": "]", "{": "}"}
_CLOSE = {"]": "[", "}": "{"}
_BRACKET_OR_QUOTE = re.compile(r"[\[\]{}\"']")
_STRING_REST = {
    '"': re.compile(r'[^"\\]*(?:\\.[^"\\]*)*"', re.S),
    "'": re.compile(r"[^'\\]*(?:\\.[^'\\]*)*'", re.S),
}
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


def _drop_closed_blocks(text: str) -> str:
    """Remove ``<think>…</think>`` blocks (and the other names), leftmost first.

    A block runs from an opening tag to the first closing tag of the same name after it, as
    the regex ``<(think|…)\\s*>.*?</\\1\\s*>`` would match, but in linear time (that regex
    rescans the rest of the text from every unclosed opening tag).
    """
    tags = list(_THINK_TAG.finditer(text))
    closes: dict[str, list[int]] = {}
    for k, tag in enumerate(tags):
        if tag.group(1):
            closes.setdefault(tag.group(2).lower(), []).append(k)
    out: list[str] = []
    pos = 0
    for k, tag in enumerate(tags):
        if tag.group(1) or tag.start() < pos:
            continue
        after = closes.get(tag.group(2).lower(), [])
        j = bisect_right(after, k)
        if j < len(after):
            out.append(text[pos : tag.start()])
            pos = tags[after[j]].end()
    out.append(text[pos:])
    return "".join(out)


def strip_think(text: str) -> str:
    """Remove reasoning blocks; an unclosed one runs to the end, a lone closing tag ends one."""
    text = _drop_closed_blocks(text)
    closes = list(_THINK_CLOSE.finditer(text))
    if closes:  # the opening tag was in the prompt (chat templates do this)
        text = text[closes[-1].end() :]
    opened = _THINK_OPEN.search(text)
    return text[: opened.start()] if opened else text


def fenced_json(text: str) -> str | None:
    """Content of the last Markdown code fence that holds a bracket, if any."""
    bodies = [m.group(1) for m in _FENCE.finditer(text) if "[" in m.group(1) or "{" in m.group(1)]
    return bodies[-1] if bodies else None


@dataclass(frozen=True)
class Span:
    """A bracketed region of the text."""

    start: int
    end: int
    closed: bool
    depth: int
    nested: bool = False
    """Lies inside the span of another candidate (lower priority for lone step objects)."""


def _prev_char(text: str, i: int, lo: int) -> str:
    """The last non-space character of ``text[lo:i]`` ("" when there is none)."""
    j = i - 1
    while j >= lo and text[j].isspace():
        j -= 1
    return text[j] if j >= lo else ""


def _scan(text: str, offset: int) -> tuple[list[Span], list[tuple[int, int]]]:
    """One pass from ``offset``: the outermost closed regions, and the still-open brackets.

    String-aware and lenient on mismatches: a closer pops the stack down to its opener, a
    closer without one is ignored. Closed regions inside a bracket that never closes count as
    outermost (so a stray ``[`` in the prose does not swallow the plan after it). Linear: the
    pass visits brackets and quotes only. The open brackets come as (start, depth), outermost
    first.
    """
    starts: list[int] = []  # the open brackets, innermost last
    depths: list[int] = []  # the nesting depth inside each so far (1: nothing inside)
    marks: list[int] = []  # len(closed) when each opened
    open_count = {"[": 0, "{": 0}
    closed: list[Span] = []
    resume = offset
    for match in _BRACKET_OR_QUOTE.finditer(text, offset):
        i = match.start()
        if i < resume:  # inside a string
            continue
        ch = text[i]
        if ch in _OPEN:
            starts.append(i)
            depths.append(1)
            marks.append(len(closed))
            open_count[ch] += 1
        elif ch in _CLOSE:
            if open_count[_CLOSE[ch]]:
                while True:
                    start, depth, mark = starts.pop(), depths.pop(), marks.pop()
                    open_count[text[start]] -= 1
                    if depths and depths[-1] <= depth:
                        depths[-1] = depth + 1
                    if text[start] == _CLOSE[ch]:
                        break
                del closed[mark:]  # regions inside this one are not outermost
                closed.append(Span(start, i + 1, True, depth))
        elif starts and (ch == '"' or _prev_char(text, i, offset) in "[{,:"):
            # Strings count inside brackets only; a single quote opens one only where a value
            # or key starts.
            rest = _STRING_REST[ch].match(text, i + 1)
            if rest is None:  # unterminated: the text ends inside the string
                break
            resume = rest.end()
    for k in range(len(depths) - 1, 0, -1):
        depths[k - 1] = max(depths[k - 1], depths[k] + 1)
    return closed, list(zip(starts, depths, strict=True))


def scan_spans(text: str) -> tuple[list[Span], int | None]:
    """Bracketed regions of ``text`` in text order, and where the last bracket still open at
    the end of the text opened (None when the text does not end inside a bracket).

    The outermost closed regions (see :func:`_scan`) and the outermost region still open at
    the end, which runs to the end of the text. That one is also re-scanned from just after
    its bracket (strings read afresh from there) for the regions inside it, at most
    :data:`MAX_RESCANS` times and over :data:`MAX_RESCAN_CHARS` characters in all.
    """
    closed, still_open = _scan(text, 0)
    last_open = still_open[-1][0] if still_open else None
    spans = {(sp.start, sp.end): sp for sp in closed}
    budget = MAX_RESCAN_CHARS
    for rescan in range(MAX_RESCANS + 1):
        if not still_open:
            break
        start, depth = still_open[0]
        spans[start, len(text)] = Span(start, len(text), False, depth)
        budget -= len(text) - start - 1
        if rescan == MAX_RESCANS or budget < 0:
            break
        closed, still_open = _scan(text, start + 1)
        for sp in closed:
            spans.setdefault((sp.start, sp.end), sp)
    return sorted(spans.values(), key=lambda sp: (sp.start, -sp.end)), last_open


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
