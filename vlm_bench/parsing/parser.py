"""``parse_plan``: model text → :class:`ParseResult`. Never raises on model output."""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

from jsonschema.protocols import Validator

from vlm_bench.parsing.answer_tag import split_answer
from vlm_bench.parsing.locate import locate_plan
from vlm_bench.parsing.schema import MAX_PLAN_STEPS, plan_json_schema, schema_validator
from vlm_bench.parsing.steps import normalise_step
from vlm_bench.parsing.vocab import SceneIds, vocabulary
from vlm_bench.types.parse import AnswerFormat, ParseCode, ParseResult


@lru_cache(maxsize=256)
def _validator(object_ids: tuple[str, ...] | None) -> Validator:
    # Length is judged before (``too_long``): no step bound here.
    return schema_validator(plan_json_schema(object_ids, max_steps=None))


def parse_plan(
    text: str, object_ids: Sequence[str] | None = None, answer_format: AnswerFormat | None = None
) -> ParseResult:
    """Parse a model's plan output.

    Args:
        text: The raw model output.
        object_ids: The scene's object and part ids. When given, references are matched to
            them (after case/separator normalisation) and others are flagged ``unknown_object``;
            the schema behind the ``valid`` tier then requires them.
        answer_format: The model's documented reasoning/answer tags (its card's
            ``answer_format``): output in exactly that form is judged by its answer alone, and
            its reasoning is kept in :attr:`ParseResult.reasoning`.

    Returns:
        The plan with per-step validity and codes, plan-level codes, the repairs applied and a
        tier: ``valid`` when the raw text is JSON that validates against
        :func:`~vlm_bench.parsing.schema.plan_json_schema` (and every step is clean),
        ``repaired`` when a plan was obtained after repair or normalisation, else ``invalid``.
        A plan of more than :data:`~vlm_bench.parsing.schema.MAX_PLAN_STEPS` steps is
        ``invalid`` with code ``too_long`` (it is neither scored step by step nor executed).
        Whatever else the parser raises on the text is caught: ``invalid`` with code
        ``error`` and the exception as ``detail``.
    """
    try:
        text = text if isinstance(text, str) else ""
        tagged = split_answer(text, answer_format) if answer_format is not None else None
        if tagged is not None:
            result = _parse(tagged.answer, object_ids)
            return result.model_copy(update={"reasoning": tagged.reasoning})
        return _parse(text, object_ids)
    # Model output is data: an exception here is a parser bug, recorded on this output only.
    except Exception as exc:  # noqa: BLE001
        return error_result(exc)


def error_result(exc: Exception) -> ParseResult:
    """The result standing for an exception raised while parsing or scoring an output."""
    detail = f"{type(exc).__name__}: {exc}"[:500]
    return ParseResult(tier="invalid", errors=(ParseCode.ERROR,), detail=detail)


def _parse(text: str, object_ids: Sequence[str] | None) -> ParseResult:
    located = locate_plan(text)
    if located.items is None or not located.items:
        errors = located.errors or (ParseCode.EMPTY_PLAN,)
        return ParseResult(tier="invalid", errors=errors, repairs=located.repairs)
    if len(located.items) > MAX_PLAN_STEPS:
        errors = (*located.errors, ParseCode.TOO_LONG)
        return ParseResult(tier="invalid", errors=errors, repairs=located.repairs)
    ids = tuple(object_ids) if object_ids is not None else None
    scene = SceneIds(ids)
    vocab = vocabulary()
    steps = tuple(normalise_step(i, raw, vocab, scene) for i, raw in enumerate(located.items))
    clean = _validator(ids).is_valid(located.items) and all(s.valid and not s.errors for s in steps)
    errors = located.errors if clean else (*located.errors, ParseCode.SCHEMA)
    return ParseResult(
        tier="valid" if clean and located.strict else "repaired",
        steps=steps,
        errors=errors,
        repairs=located.repairs,
    )
