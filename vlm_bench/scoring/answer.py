"""Score one answer for one episode: the scoring path of runs, ``vlm-bench score`` and the
exported dataset (:func:`score_answer`), importable without the simulator.

:func:`evaluate_answer` is the one place a model's text becomes a parse, a plan, the paper's
scores and the error tags; a run's records and :func:`score_answer` both go through it.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

from pydantic import TypeAdapter, ValidationError

from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import get_task
from vlm_bench.errors import ConfigError
from vlm_bench.parsing import error_result, parse_plan
from vlm_bench.scoring.metrics import score_plan
from vlm_bench.types.benchmark_version import (
    BENCHMARK_VERSION,
    BenchmarkVersionError,
    version_label,
)
from vlm_bench.types.parse import AnswerFormat, ParseResult
from vlm_bench.types.plan import PlanStep, plan_to_json
from vlm_bench.types.records import OutputScore
from vlm_bench.types.scores import PlanScores, ScoringConfig
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant

_PLAN = TypeAdapter(tuple[PlanStep, ...])


@dataclass(frozen=True)
class Evaluation:
    """What one model output amounts to for one episode."""

    parse: ParseResult
    plan: list[dict[str, Any]]
    scores: PlanScores
    error_tags: tuple[str, ...]


def evaluate_answer(
    text: str,
    object_ids: Sequence[str],
    gt_plan: Sequence[PlanStep],
    scoring: ScoringConfig,
    answer_format: AnswerFormat | None = None,
) -> Evaluation:
    """Parse ``text`` against the episode's object ids (and the model's documented answer
    format, if any) and score it against its GT plan. Never raises on model output.

    Returns:
        The parse result, the valid predicted steps in the paper's JSON format, the scores and
        the error tags: parser codes, then planning error types (duplicates removed).
    """
    parsed = parse_plan(text, list(object_ids), answer_format)  # never raises
    try:
        scores = score_plan(parsed, tuple(gt_plan), scoring)
    # One output must not stop a run, nor every resume of it (its answer is cached): what
    # scoring raises is this output's recorded result, parse code ``error``.
    except Exception as exc:  # noqa: BLE001
        parsed = error_result(exc)
        scores = score_plan(parsed, tuple(gt_plan), scoring)
    tags = dict.fromkeys(str(code) for code in parsed.all_errors())
    tags.update(dict.fromkeys(str(err) for err in scores.error_types))
    return Evaluation(parsed, plan_to_json(parsed.valid_steps()), scores, tuple(tags))


@dataclass(frozen=True)
class _Target:
    """What an answer is scored against: the episode's identity, ids and GT plan."""

    task_id: str
    seed: int
    variant: InstructionVariant
    object_ids: tuple[str, ...]
    gt_plan: tuple[PlanStep, ...]


def _split_key(key: str) -> tuple[str, int, InstructionVariant]:
    parts = key.split("/")
    if len(parts) != 3 or not parts[1].isdigit() or parts[2] not in INSTRUCTION_VARIANTS:
        raise ConfigError(
            f"episode key must be task_id/seed/variant (e.g. drawer_interaction/0/explicit), "
            f"got {key!r}"
        )
    variant: InstructionVariant = "explicit" if parts[2] == "explicit" else "implicit"
    return parts[0], int(parts[1]), variant


@cache
def _committed(task_id: str) -> dict[int, tuple[tuple[str, ...], tuple[PlanStep, ...]]]:
    return {
        ep.seed: (tuple(ep.object_ids()), ep.gt_plan)
        for ep in load_materialised(get_task(task_id)).episodes
    }


def _target_of_key(key: str) -> _Target:
    task_id, seed, variant = _split_key(key)
    task_id = get_task(task_id).id  # unknown task: lists the valid ids
    found = _committed(task_id).get(seed)
    if found is None:
        raise ConfigError(
            f"episode {key} is not in the committed ground truth of benchmark version "
            f"{BENCHMARK_VERSION}; score it with its dataset row instead of its key"
        )
    return _Target(task_id, seed, variant, *found)


def _target_of_row(row: Mapping[str, Any]) -> _Target:
    missing = [f for f in ("key", "benchmark_version", "objects", "gt_plan") if f not in row]
    if missing:
        raise ConfigError(f"not a vlm-bench dataset row: it lacks {', '.join(missing)}")
    version = int(row["benchmark_version"])
    if version != BENCHMARK_VERSION:
        raise BenchmarkVersionError(
            f"dataset row {row['key']} is benchmark version {version_label(version)}; this "
            f"release scores version {BENCHMARK_VERSION}: export the dataset again with this "
            "release, or score with the release that exported it"
        )
    task_id, seed, variant = _split_key(str(row["key"]))
    try:
        steps = json.loads(row["gt_plan"])
        plan = _PLAN.validate_python(
            [{k: v for k, v in s.items() if k != "subtask"} for s in steps]
        )
    except (ValueError, TypeError, AttributeError, ValidationError):
        raise ConfigError(f"dataset row {row['key']}: gt_plan is not a plan") from None
    return _Target(task_id, seed, variant, tuple(row["objects"]), plan)


def score_answer(
    row_or_key: Mapping[str, Any] | str,
    answer: str,
    scoring: ScoringConfig | None = None,
) -> OutputScore:
    """Score one model answer for one episode, as ``vlm-bench score`` does; needs no simulator.

    Args:
        row_or_key: A row of the exported dataset (a mapping with at least ``key``,
            ``benchmark_version``, ``objects`` and ``gt_plan``, e.g. what ``datasets`` yields,
            or ``DatasetRow.model_dump()``), or an episode key ``task_id/seed/variant`` of the
            committed ground truth.
        answer: The model's raw answer text.
        scoring: Metric options (default: the paper's).

    Returns:
        The parse, plan, GT plan, scores (``.scores.s_plan``, ``s_loc``, ``s_obj``,
        ``s_skill``, ``s_total``, ``succ``) and error tags.

    Raises:
        BenchmarkVersionError: A row of another benchmark version. ConfigError: A malformed
            key or row, or a key outside the committed ground truth. UnknownNameError: An
            unknown task id.
    """
    if isinstance(row_or_key, str):
        target = _target_of_key(row_or_key)
    else:
        target = _target_of_row(row_or_key)
    ev = evaluate_answer(answer, target.object_ids, target.gt_plan, scoring or ScoringConfig())
    return OutputScore(
        task_id=target.task_id,
        seed=target.seed,
        instruction=target.variant,
        parse=ev.parse,
        plan=ev.plan,
        gt_plan=plan_to_json(target.gt_plan),
        scores=ev.scores,
        error_tags=ev.error_tags,
    )
