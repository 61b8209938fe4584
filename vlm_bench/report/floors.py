"""The ``blind`` floor on the same episodes: what S_loc a planner earns without the images.

Every summary shows a model's S_loc above this floor (``Loc_over_blind``): the part of its
localisation score that the images, not the benchmark's direction statistics, account for.
"""

from __future__ import annotations

import json

from pydantic import TypeAdapter

from vlm_bench.backends.blind_planner import blind_plan
from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import score_plan
from vlm_bench.types.plan import ArmStep, PlanStep, plan_to_json
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.scores import ScoringConfig

_PLAN = TypeAdapter(list[PlanStep])


def blind_s_loc(record: EpisodeRecord, scoring: ScoringConfig) -> float | None:
    """S_loc of the ``blind`` planner on the record's episode (None without a GT plan)."""
    if not record.gt_plan:
        return None
    gt = _PLAN.validate_python(
        [{k: v for k, v in s.items() if k != "subtask"} for s in record.gt_plan]
    )
    arm = [s for s in gt if isinstance(s, ArmStep)]
    ids = sorted({r for s in arm for r in (s.object, s.target) if r is not None})
    plan = blind_plan(record.task_id, record.seed, arm)
    parsed = parse_plan(json.dumps(plan_to_json(plan)), ids)
    return score_plan(parsed, gt, scoring).s_loc
