"""Deterministic repair: from raw model text to a JSON value that may hold a plan.

Order: strip reasoning blocks, take the last code fence that holds JSON, cut every top-level
JSON array/object out of the prose, load each (``json`` first, ``json-repair`` when that fails),
and pick the candidate that holds a plan (see :func:`find_json`).
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import json_repair

from vlm_bench.types.parse import Repair

MAX_REPAIRS = 64  # json-repair runs on at most this many spans (the last ones) per output
MAX_DEPTH = 32  # plans are 2–3 levels deep; deeper spans are not parsed (recursion limits)
_MAX_RESCANS = 4  # how many times an unclosed span is re-scanned for closed spans inside it

_THINK_BLOCK = re.compile(r"<(think|thinking|reasoning)\s*>.*?</\1\s*>", re.S | re.I)
_THINK_CLOSE = re.compile(r"</(?:think|thinking|reasoning)\s*>", re.I)
_THINK_OPEN = re.compile(r"<(?:think|thinking|reasoning)\s*>", re.I)
_FENCE = re.compile(r"```[A-Za-z0-9_+-]*[ \t]*\n?(.*?)(?:```|\Z)", re.S)
_OPEN = {"[": "]", "{": "}"}
_CLOSE = {"]": "[", "}": "{"}


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def strict_loads(text: str) -> tuple[Any, bool]:
    """``json.loads`` that rejects NaN/Infinity and deep nesting; returns (value, ok)."""
    try:
        return json.loads(text, parse_constant=_reject_constant), True
    except (ValueError, RecursionError):
        return None, False


def strip_think(text: str) -> str:
    """Remove reasoning blocks; an unclosed one runs to the end, a lone closing tag ends one."""
    text = _THINK_BLOCK.sub("", text)
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
    """A top-level bracketed region of the text."""

    start: int
    end: int
    closed: bool
    depth: int
    nested: bool = False
    """Found by re-scanning inside an unclosed span (lower priority)."""


def _scan(text: str, offset: int, nested: bool = False) -> Iterator[Span]:
    """Top-level ``[...]``/``{...}`` spans from ``offset``; string-aware, lenient on mismatches."""
    stack: list[str] = []
    start, depth, quote, prev = 0, 0, "", ""
    i = offset
    while i < len(text):
        ch = text[i]
        if quote:
            if ch == "\\":
                i += 1
            elif ch == quote:
                quote = ""
        elif stack and (ch == '"' or (ch == "'" and prev in "[{,:")):
            quote = ch  # a single quote opens a string only where a value or key starts
        elif ch in _OPEN:
            if not stack:
                start, depth = i, 0
            stack.append(ch)
            depth = max(depth, len(stack))
        elif ch in _CLOSE and _CLOSE[ch] in stack:
            while stack.pop() != _CLOSE[ch]:
                pass
            if not stack:
                yield Span(start, i + 1, True, depth, nested)
        if not ch.isspace():
            prev = ch
        i += 1
    if stack:
        yield Span(start, len(text), False, depth, nested)


def scan_spans(text: str) -> tuple[list[Span], bool]:
    """All top-level spans, and whether the text ends inside one.

    An unclosed last span is also searched for closed spans inside it, so a stray ``[`` in the
    prose does not swallow the plan that follows it.
    """
    spans = list(_scan(text, 0))
    truncated = bool(spans) and not spans[-1].closed
    for _ in range(_MAX_RESCANS):
        if not spans or spans[-1].closed:
            break
        spans.extend(_scan(text, spans[-1].start + 1, nested=True))
    return spans, truncated


def load_span(text: str, repair: bool = True) -> tuple[Any, bool]:
    """Load JSON text, repairing it when strict loading fails; returns (value, repaired).

    Text without ``{`` and ``:`` cannot hold a step object, so it is not repaired (bracketed
    prose is common and json-repair is slow on it); nor is any text when ``repair`` is False.
    """
    value, ok = strict_loads(text)
    if ok:
        return value, False
    if not repair or "{" not in text or ":" not in text:
        return None, False
    try:
        repaired = json_repair.loads(text)
    # json-repair applies open-ended heuristics to arbitrary text; any failure means "no JSON".
    except Exception:  # noqa: BLE001
        return None, True
    if isinstance(repaired, tuple):  # only with logging=True, which is not used
        repaired = repaired[0]
    return (None if repaired == "" else repaired), True


@dataclass(frozen=True)
class Candidate:
    """A JSON value loaded from one span of the text."""

    value: Any
    span: Span
    repairs: tuple[Repair, ...]


def candidates(text: str) -> tuple[list[Candidate], bool]:
    """Load the top-level spans of ``text`` in text order; also says if the text ends inside one.

    Every span is tried as strict JSON; json-repair runs on the last :data:`MAX_REPAIRS` spans
    that need it only, which bounds the time on long outputs (the plan usually comes last).
    """
    spans, truncated = scan_spans(text)
    stripped = text.strip()
    out: list[Candidate] = []
    budget = MAX_REPAIRS
    for span in sorted(spans, key=lambda sp: sp.start, reverse=True):
        if span.depth > MAX_DEPTH:
            continue
        chunk = text[span.start : span.end]
        value, repaired = load_span(chunk, repair=budget > 0)
        budget -= repaired
        if value is None:
            continue
        repairs = (Repair.EXTRACT,) if chunk.strip() != stripped else ()
        out.append(Candidate(value, span, repairs + ((Repair.JSON_REPAIR,) if repaired else ())))
    return out[::-1], truncated
