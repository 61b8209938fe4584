"""A lenient, string-aware bracket matcher: the bracketed regions of a text that may hold JSON.

Linear in the text: a pass visits brackets and quotes only, and the region still open at the
end is re-scanned a bounded number of times (the ``MAX_`` constants below).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

MAX_RESCANS = 4  # how many times a region still open at the end is re-scanned for regions inside it
MAX_RESCAN_CHARS = 200_000  # ... reading at most this many characters in all
_OPEN = {"[": "]", "{": "}"}
_CLOSE = {"]": "[", "}": "{"}
_BRACKET_OR_QUOTE = re.compile(r"[\[\]{}\"']")
_STRING_REST = {
    '"': re.compile(r'[^"\\]*(?:\\.[^"\\]*)*"', re.S),
    "'": re.compile(r"[^'\\]*(?:\\.[^'\\]*)*'", re.S),
}


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
