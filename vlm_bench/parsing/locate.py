"""Find the plan array in model text: the strict path, then the repair path.

Choice rules, in order:

1. The whole text is strict JSON: use it (a JSON *string* holding JSON is decoded once).
2. Otherwise strip reasoning blocks, then try the last code fence that holds JSON, then the
   whole remaining text. In each, the candidates are the strict JSON arrays/objects found
   anywhere in the text and the repaired bracketed regions that are not strict JSON (see
   :func:`~vlm_bench.parsing.extract.candidates`). A candidate holding a plan array (directly
   or through a wrapper) wins over lone step objects. Among plans:

   * one whose region holds a better plan loses to it: one with fewer non-step elements, or
     as many and more elements (a stray ``[`` in the prose opened this region, and repair
     swallowed the prose into the plan, or mangled it);
   * otherwise a plan inside another plan's region loses to it (the outer one, unwrapped);
   * among the rest the *last* wins (models revise drafts; the final answer comes last).

   Several lone step objects (JSON lines) are joined into one plan, those inside another
   candidate's region only when there are no others.
3. Text longer than :data:`MAX_SEARCH_CHARS` is searched in its end, then its start
   (:func:`_windows`, marked ``window``).
4. ``truncated`` is reported when the plan used comes from a region still open at the end of
   the text, or when a bracket opened after it is still open at the end (the output was cut
   after the plan); when there is no plan, when the text ends inside a bracket. A stray ``[``
   in the prose *before* the plan does not count.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from vlm_bench.parsing.extract import Candidate, candidates, strict_loads
from vlm_bench.parsing.vocab import KEY_ALIASES, token
from vlm_bench.parsing.wrappers import fenced_json, strip_think
from vlm_bench.types.parse import ParseCode, Repair

# Keys under which models nest the plan array (compared as tokens).
PLAN_KEYS = frozenset({"plan", "steps", "subtasks", "actions", "tasks", "taskplan", "sequence"})
_STEP_KEYS = frozenset({"tasktype", "skill", "direction", "object"})
_MAX_WRAPPING = 4
MAX_SEARCH_CHARS = 262_144
"""Longest text (after reasoning blocks are stripped) searched whole for a plan; see
:func:`_windows` for longer text."""

Kind = Literal["plan", "step", "empty", "none"]


@dataclass(frozen=True)
class Unwrapped:
    """A JSON value seen as a plan."""

    items: list[Any] | None
    kind: Kind
    unwrapped: bool = False


def _is_step(value: dict[str, Any]) -> bool:
    return any(KEY_ALIASES.get(token(str(k))) in _STEP_KEYS for k in value)


def unwrap(value: Any, depth: int = 0) -> Unwrapped:
    """See ``value`` as a plan: a list holding step objects, a wrapper of one, or one step.

    A step object is a JSON object with at least one step key (``tasktype``, ``skill``,
    ``direction``, ``object`` or an alias); a list of other objects is not a plan.
    """
    if depth > _MAX_WRAPPING:
        return Unwrapped(None, "none")
    if isinstance(value, list):
        if any(isinstance(x, dict) and _is_step(x) for x in value):
            return Unwrapped(value, "plan", depth > 0)
        if len(value) == 1 and isinstance(value[0], list | dict):
            inner = unwrap(value[0], depth + 1)
            return Unwrapped(inner.items, inner.kind, True)
        return Unwrapped(None, "empty" if not value else "none", depth > 0)
    if not isinstance(value, dict):
        return Unwrapped(None, "none")
    for key, inner_value in value.items():
        if token(str(key)) in PLAN_KEYS and isinstance(inner_value, list | dict):
            inner = unwrap(inner_value, depth + 1)
            if inner.kind != "none":
                return Unwrapped(inner.items, "plan" if inner.kind == "step" else inner.kind, True)
    if _is_step(value):
        return Unwrapped([value], "step", True)
    nested = [v for v in value.values() if isinstance(v, list | dict)]
    if len(nested) == 1:
        inner = unwrap(nested[0], depth + 1)
        return Unwrapped(inner.items, inner.kind, True)
    return Unwrapped(None, "none")


@dataclass(frozen=True)
class Located:
    """The plan array found in the text (None when there is none), with how it was found."""

    items: list[Any] | None
    repairs: tuple[Repair, ...] = ()
    errors: tuple[ParseCode, ...] = ()
    strict: bool = False
    """The whole text was strict JSON holding the plan array itself (no repair, no unwrap)."""


def _junk(items: list[Any]) -> int:
    """How many elements of a plan array are not step objects."""
    return sum(not (isinstance(x, dict) and _is_step(x)) for x in items)


def _best_plan(plans: list[tuple[Unwrapped, Candidate]]) -> tuple[Unwrapped, Candidate]:
    """The plan candidate to use, by the module's choice rules (linear after a sort)."""
    order = sorted(range(len(plans)), key=lambda k: (plans[k][1].span.start, -plans[k][1].span.end))
    parent = [-1] * len(plans)
    stack: list[int] = []
    for k in order:  # the innermost plan region holding each one
        while stack and plans[stack[-1]][1].span.end < plans[k][1].span.end:
            stack.pop()
        parent[k] = stack[-1] if stack else -1
        stack.append(k)
    # Better: fewer non-step elements, then more elements.
    score = [(-_junk(u.items or []), len(u.items or [])) for u, _ in plans]
    inner: list[tuple[int, int] | None] = [None] * len(plans)  # the best plan inside each one
    for k in reversed(order):
        p = parent[k]
        if p >= 0:
            inner[p] = max(x for x in (inner[p], score[k], inner[k]) if x is not None)
    kept = [False] * len(plans)
    below_kept = [False] * len(plans)
    for k in order:
        p = parent[k]
        below_kept[k] = p >= 0 and (kept[p] or below_kept[p])
        best_inside = inner[k]
        kept[k] = (best_inside is None or best_inside <= score[k]) and not below_kept[k]
    return plans[max((k for k in order if kept[k]), key=lambda k: plans[k][1].span.start)]


def _truncated(used: list[Candidate], last_open: int | None) -> tuple[ParseCode, ...]:
    """TRUNCATED when a used region is still open at the end, or one opened after them is."""
    still_open = not all(c.span.closed for c in used)
    after = last_open is not None and last_open >= max(c.span.end for c in used)
    return (ParseCode.TRUNCATED,) if still_open or after else ()


def _pick(cands: list[Candidate], last_open: int | None) -> Located | None:
    """The plan among the candidates, by the module's choice rules."""
    seen = [(unwrap(c.value), c) for c in cands]
    plans = [(u, c) for u, c in seen if u.kind == "plan"]
    if plans:
        u, c = _best_plan(plans)
        unwrapped = (Repair.UNWRAP,) if u.unwrapped else ()
        return Located(u.items, c.repairs + unwrapped, _truncated([c], last_open))
    steps = [(u, c) for u, c in seen if u.kind == "step" and not c.span.nested]
    steps = steps or [(u, c) for u, c in seen if u.kind == "step"]
    if not steps:
        return None
    repairs = dict.fromkeys(r for _, c in steps for r in c.repairs)
    repairs[Repair.JOIN_OBJECTS if len(steps) > 1 else Repair.UNWRAP] = None
    items = [u.items[0] for u, _ in steps if u.items]
    return Located(items, tuple(repairs), _truncated([c for _, c in steps], last_open))


def _failure(cands: list[Candidate]) -> ParseCode:
    if not cands:
        return ParseCode.NO_JSON
    if any(unwrap(c.value).kind == "empty" for c in cands):
        return ParseCode.EMPTY_PLAN
    return ParseCode.NOT_A_PLAN


def locate_plan(text: str, _decoded: bool = False) -> Located:
    """Find the plan array in ``text``; never raises."""
    if not text.strip():
        return Located(None, errors=(ParseCode.EMPTY,))
    value, ok = strict_loads(text)
    if ok and isinstance(value, str) and not _decoded:
        inner = locate_plan(value, _decoded=True)
        return Located(inner.items, (Repair.DECODE_STRING, *inner.repairs), inner.errors)
    if ok:
        u = unwrap(value)
        if u.kind in ("plan", "step"):
            unwrapped = (Repair.UNWRAP,) if u.unwrapped else ()
            return Located(u.items, unwrapped, strict=not u.unwrapped)
        code = ParseCode.EMPTY_PLAN if u.kind == "empty" else ParseCode.NOT_A_PLAN
        return Located(None, errors=(code,))
    body = strip_think(text)
    think = (Repair.STRIP_THINK,) if body != text else ()
    attempts = _windows(body, ())
    fence = fenced_json(body)
    if fence is not None:
        attempts = _windows(fence, (Repair.STRIP_FENCE,)) + attempts
    failure = ParseCode.NO_JSON
    truncated: tuple[ParseCode, ...] = ()
    for chunk, repairs, at_end in attempts:
        cands, last_open = candidates(chunk)
        if not at_end:
            last_open = None  # the cut is not the end of the output
        found = _pick(cands, last_open)
        if found is not None:
            return Located(found.items, think + repairs + found.repairs, found.errors)
        failure = _failure(cands) if failure == ParseCode.NO_JSON else failure
        if at_end:
            truncated = (ParseCode.TRUNCATED,) if last_open is not None else ()
    window = (Repair.WINDOW,) if any(Repair.WINDOW in r for _, r, _ in attempts) else ()
    return Located(None, think + window, (*truncated, failure))


def _windows(text: str, repairs: tuple[Repair, ...]) -> list[tuple[str, tuple[Repair, ...], bool]]:
    """The parts of ``text`` searched, each with its repairs and whether it ends the text.

    Text up to :data:`MAX_SEARCH_CHARS` is searched whole; longer text in its last half of
    that bound (models give the final answer last), then its first half (a model that loops
    after its answer), marked :attr:`Repair.WINDOW`. Parsing time is bounded accordingly.
    """
    if len(text) <= MAX_SEARCH_CHARS:
        return [(text, repairs, True)]
    half = MAX_SEARCH_CHARS // 2
    marked = (*repairs, Repair.WINDOW)
    return [(text[-half:], marked, True), (text[:half], marked, False)]
