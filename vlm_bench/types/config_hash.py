"""The one rule that keeps configuration hashes stable as configurations grow.

A field enters a configuration's hash only when it differs from its default, at any depth of
nesting, so a field added later leaves the hash of every configuration written before it (and
its default run folder) as it was, with nothing to list. The fields hashed even at their default
are those of the first releases, which always were: :data:`HASHED_AT_DEFAULT` is frozen history,
never extended. A field whose default changed after it was added compares with the value every
configuration had before it existed (:data:`VALUE_BEFORE`).
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel

HASHED_AT_DEFAULT: dict[str, frozenset[str]] = {
    "RunConfig": frozenset(
        (
            "model",
            "backend_args",
            "tasks",
            "suite",
            "seeds",
            "instructions",
            "views",
            "resolution",
            "labels",
            "k_shot",
            "few_shot_seed",
            "object_list",
            "generation",
            "scoring",
            "execute",
            "benchmark_version",
        )
    ),
    "GenerationConfig": frozenset(
        ("max_new_tokens", "temperature", "top_p", "seed", "constrained", "batch_size")
    ),
    "ScoringConfig": frozenset(("alpha", "weights", "neighbour_credit", "empty_gt")),
    "ScoreWeights": frozenset(("*",)),
    "PerturbConfig": frozenset(("slip", "bump")),
}
"""Fields hashed even at their default, by model: those of the first releases (``*``: all)."""

VALUE_BEFORE: dict[tuple[str, str], Any] = {("ScoringConfig", "loc_alignment"): "order"}
"""Fields whose default changed after they were added: the value before they existed (what an
older manifest, which lacks them, means)."""


def _left_out(model: BaseModel, name: str, value: Any) -> bool:
    kind = type(model).__name__
    kept = HASHED_AT_DEFAULT.get(kind, frozenset())
    if name in kept or "*" in kept:
        return False
    if (kind, name) in VALUE_BEFORE:
        return bool(value == VALUE_BEFORE[kind, name])
    field = type(model).model_fields.get(name)
    default = field.get_default(call_default_factory=True) if field is not None else 0
    return bool(value == default)


def stable_fields(model: BaseModel) -> dict[str, Any]:
    """``model`` as JSON, each nested model the same way, without the fields the rule leaves
    out (module doc)."""
    data: dict[str, Any] = model.model_dump(mode="json")
    values = {n: getattr(model, n) for n in type(model).model_fields}
    values.update(model.model_extra or {})
    for name, value in values.items():
        if _left_out(model, name, value):
            del data[name]
        elif isinstance(value, BaseModel):
            data[name] = stable_fields(value)
    return data
