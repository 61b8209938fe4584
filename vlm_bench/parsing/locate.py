"""Find the plan array in model text: the strict path, then the repair path.

Choice rules, in order:

1. The whole text is strict JSON: use it (a JSON *string* holding JSON is decoded once).
2. Otherwise strip reasoning blocks, then try the last code fence that holds JSON, then the
   whole remaining text. In each, every top-level JSON array/object is a candidate; a candidate
   holding a plan array (directly or through a wrapper) wins over lone step objects, and among
   equals the *last* wins (models revise drafts; the final answer comes last). Several lone step
   objects (JSON lines) are joined into one plan.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from vlm_bench.parsing.extract import Candidate, candidates, fenced_json, strict_loads, strip_think
from vlm_bench.parsing.vocab import KEY_ALIASES, token
from vlm_bench.types.parse import ParseCode, Repair

# Keys under which models nest the plan array (compared as tokens).
PLAN_KEYS = frozenset({"plan", "steps", "subtasks", "actions", "tasks", "taskplan", "sequence"})
_STEP_KEYS = frozenset({"tasktype", "skill", "direction", "object"})
_MAX_WRAPPING = 4

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


def _pick(cands: list[Candidate]) -> Located | None:
    """The plan among the candidates, by the module's choice rules."""
    seen = [(unwrap(c.value), c) for c in cands]
    plans = [(u, c) for u, c in seen if u.kind == "plan"]
    if plans:
        u, c = max(enumerate(plans), key=lambda p: (not p[1][1].span.nested, p[0]))[1]
        return Located(u.items, c.repairs + ((Repair.UNWRAP,) if u.unwrapped else ()))
    steps = [(u, c) for u, c in seen if u.kind == "step" and not c.span.nested]
    steps = steps or [(u, c) for u, c in seen if u.kind == "step"]
    if not steps:
        return None
    repairs = dict.fromkeys(r for _, c in steps for r in c.repairs)
    repairs[Repair.JOIN_OBJECTS if len(steps) > 1 else Repair.UNWRAP] = None
    return Located([u.items[0] for u, _ in steps if u.items], tuple(repairs))


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
    attempts: list[tuple[str, tuple[Repair, ...]]] = [(body, ())]
    fence = fenced_json(body)
    if fence is not None:
        attempts.insert(0, (fence, (Repair.STRIP_FENCE,)))
    failure = ParseCode.NO_JSON
    truncated = False
    for chunk, fenced in attempts:
        cands, truncated = candidates(chunk)
        found = _pick(cands)
        trunc = (ParseCode.TRUNCATED,) if truncated else ()
        if found is not None:
            return Located(found.items, think + fenced + found.repairs, trunc)
        failure = _failure(cands) if failure == ParseCode.NO_JSON else failure
    return Located(None, think, ((ParseCode.TRUNCATED,) if truncated else ()) + (failure,))
