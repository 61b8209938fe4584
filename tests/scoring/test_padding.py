"""S_loc's padding diagnostics, hand-computed: n_move_pred, S_loc_prec and the frame columns."""

from __future__ import annotations

import json
import math
from typing import Any

from vlm_bench.parsing import parse_plan
from vlm_bench.report.dataframe import records_frame
from vlm_bench.scoring import score_plan
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.scores import EmptyGtPolicy, PlanScores, ScoringConfig

IDS = ["cube", "basket"]
D = Direction
# GT: front, pick cube, place basket: one move in two segments.
GT: list[UavStep | ArmStep] = [
    UavStep(direction=D.FRONT),
    ArmStep(object="cube", skill="pick"),
    ArmStep(object="basket", skill="place"),
]


def uav(direction: str) -> dict[str, Any]:
    return {"tasktype": "UAV", "direction": direction}


def arm(skill: str, obj: str) -> dict[str, Any]:
    return {"tasktype": "ARM", "skill": skill, "object": obj}


def score(pred: list[Any], gt: list[UavStep | ArmStep] = GT, **config: Any) -> PlanScores:
    return score_plan(parse_plan(json.dumps(pred), IDS), gt, ScoringConfig(**config))


def test_a_guess_in_every_segment_keeps_s_loc_but_not_its_precision() -> None:
    # The padding example of docs/metrics.md: up + front before the pick, a left before the
    # place. Credits: front = 100 (the GT's one move); the up and the left have no partner.
    s = score([uav("up"), uav("front"), arm("pick", "cube"), uav("left"), arm("place", "basket")])
    assert s.s_loc == 100.0  # 100 / N_move = 100 / 1
    assert s.n_move_pred == 3
    assert math.isclose(s.s_loc_precision, 100.0 / 3)  # 100 / max(1, 3)


def test_precision_equals_s_loc_without_padding() -> None:
    s = score([uav("frontleft"), arm("pick", "cube"), arm("place", "basket")])
    assert (s.s_loc, s.s_loc_precision, s.n_move_pred) == (40.0, 40.0, 1)  # neighbour credit
    s = score([arm("pick", "cube"), arm("place", "basket")])  # a missing move: no partner
    assert (s.s_loc, s.s_loc_precision, s.n_move_pred) == (0.0, 0.0, 0)


def test_invalid_uav_steps_count_as_predicted_moves() -> None:
    s = score([uav("towards the cube"), uav("front"), arm("pick", "cube"), arm("place", "basket")])
    # Both are UAV-typed: the invalid one takes the horizontal slot and scores 0, front pairs
    # with nothing. S_loc = 0; precision 0 / max(1, 2) = 0.
    assert (s.n_move_pred, s.s_loc, s.s_loc_precision) == (2, 0.0, 0.0)


def test_no_gt_move_follows_the_empty_gt_policy() -> None:
    gt: list[UavStep | ArmStep] = [ArmStep(object="cube", skill="pick")]
    still = score([arm("pick", "cube")], gt)
    assert (still.s_loc, still.s_loc_precision) == (100.0, 100.0)
    moved = score([uav("front"), arm("pick", "cube")], gt)
    assert (moved.s_loc, moved.s_loc_precision, moved.n_move_pred) == (0.0, 0.0, 1)
    full = score([uav("front"), arm("pick", "cube")], gt, empty_gt=EmptyGtPolicy.FULL)
    assert (full.s_loc, full.s_loc_precision) == (100.0, 100.0)


def test_no_usable_plan_scores_zero() -> None:
    s = score_plan(parse_plan("I cannot help", IDS), GT)
    assert (s.n_move_pred, s.s_loc_precision) == (0, 0.0)


def _record(scores: PlanScores | dict[str, Any]) -> EpisodeRecord:
    return EpisodeRecord.model_validate(
        {
            "run_id": "r",
            "key": "k",
            "task_id": "t",
            "suite": "base_manipulation",
            "seed": 1,
            "variant": "explicit",
            "model": "m",
            "status": "ok",
            "scores": scores if isinstance(scores, dict) else scores.model_dump(mode="json"),
        }
    )


def test_frame_columns_move_ratio_and_precision() -> None:
    padded = score(
        [uav("up"), uav("front"), arm("pick", "cube"), uav("left"), arm("place", "basket")]
    )
    row = records_frame([_record(padded)]).iloc[0]
    assert row.Move_ratio == 3.0  # 3 predicted moves / 1 GT move
    assert math.isclose(row.S_loc_prec, 100.0 / 3)


def test_records_from_before_the_fields_load_with_nan_columns() -> None:
    old = score([uav("front"), arm("pick", "cube"), arm("place", "basket")]).model_dump(mode="json")
    del old["n_move_pred"], old["s_loc_precision"]
    record = _record(old)
    assert record.scores is not None and record.scores.n_move_pred == 0
    row = records_frame([record]).iloc[0]
    assert math.isnan(row.Move_ratio) and math.isnan(row.S_loc_prec)
    assert row.S_loc == 100.0
