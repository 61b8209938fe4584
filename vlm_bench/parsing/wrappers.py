"""What surrounds the JSON in a model's answer: reasoning blocks and Markdown code fences."""

from __future__ import annotations

import re
from bisect import bisect_right

_THINK_TAG = re.compile(r"<(/?)(think|thinking|reasoning)\s*>", re.I)
_THINK_CLOSE = re.compile(r"</(?:think|thinking|reasoning)\s*>", re.I)
_THINK_OPEN = re.compile(r"<(?:think|thinking|reasoning)\s*>", re.I)
_FENCE = re.compile(r"```[A-Za-z0-9_+-]*[ \t]*\n?(.*?)(?:```|\Z)", re.S)


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
