"""The paper-layout summary: hand-computed cells, suite-averaged overall, both, errors."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pandas as pd
import pytest

from vlm_bench.report import records_frame, summary_long, summary_markdown, summary_wide
from vlm_bench.report.tables import summary_rich, write_summary
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.scores import PlanScores


@pytest.fixture
def rec(make_scores: Callable[..., PlanScores]) -> Callable[..., EpisodeRecord]:
    """A record whose four planning metrics equal ``total``; None: a backend error."""

    def build(
        model: str, suite: str, seed: int, variant: str, total: float | None, succ: bool = False
    ) -> EpisodeRecord:
        ok = total is not None
        return EpisodeRecord(
            run_id="r",
            key=f"{suite}_t/{seed}/{variant}",
            task_id=f"{suite}_t",
            suite=suite,
            seed=seed,
            variant=variant,
            model=model,
            scores=make_scores(total, total, total, total, succ) if total is not None else None,
            status="ok" if ok else "error",
            backend_error=None if ok else "timeout",
        )

    return build


@pytest.fixture
def frame(rec: Callable[..., EpisodeRecord]) -> pd.DataFrame:
    # Base: 1 episode at 100 (exact). Long-horizon: 3 episodes at 0, 0, 60 and one error.
    # Episode-weighted overall would be (100 + 60) / 4 = 40; suite-averaged is (100 + 20) / 2.
    recs = [
        rec("m1", "base_manipulation", 0, "explicit", 100.0, succ=True),
        rec("m1", "long_horizon", 0, "explicit", 0.0),
        rec("m1", "long_horizon", 1, "explicit", 0.0),
        rec("m1", "long_horizon", 2, "explicit", 60.0),
        rec("m1", "long_horizon", 3, "explicit", None),
        rec("m1", "base_manipulation", 0, "implicit", 50.0),
        rec("m1", "long_horizon", 0, "implicit", 10.0),
        rec("m2", "base_manipulation", 0, "explicit", 30.0),
    ]
    return records_frame(recs)


def _row(long: pd.DataFrame, model: str, instruction: str, suite: str) -> pd.Series:
    hit = long[(long.model == model) & (long.instruction == instruction) & (long.suite == suite)]
    assert len(hit) == 1, hit
    return hit.iloc[0]


def test_suite_cells_are_episode_means_with_succ_percent(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    base = _row(long, "m1", "explicit", "base_manipulation")
    assert (base.S_total, base.Succ, base.n, base.n_error) == (100.0, 100.0, 1, 0)
    lh = _row(long, "m1", "explicit", "long_horizon")
    assert lh.S_plan == pytest.approx(20.0) and lh.Succ == 0.0
    assert (lh.n, lh.n_error) == (3, 1)


def test_overall_is_the_unweighted_mean_of_suite_cells(frame: pd.DataFrame) -> None:
    overall = _row(summary_long(frame), "m1", "explicit", "overall")
    assert overall.S_total == pytest.approx(60.0)  # (100 + 20) / 2, not (100+0+0+60) / 4 = 40
    assert overall.Succ == pytest.approx(50.0)  # (100 % + 0 %) / 2
    assert (overall.n, overall.n_error) == (4, 1)


def test_both_averages_the_instruction_cells(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    both_base = _row(long, "m1", "both", "base_manipulation")
    assert both_base.S_total == pytest.approx(75.0)  # (100 + 50) / 2
    both_overall = _row(long, "m1", "both", "overall")
    # Paper's per-model overall: mean of the four instruction × suite cells.
    assert both_overall.S_total == pytest.approx((100 + 20 + 50 + 10) / 4)
    assert not ((long.model == "m2") & (long.instruction == "both")).any()  # one variant only


def test_rows_are_ordered_like_the_paper(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    m1 = long[long.model == "m1"]
    assert list(dict.fromkeys(m1.instruction)) == ["explicit", "implicit", "both"]
    assert list(m1[m1.instruction == "explicit"].suite) == [
        "base_manipulation",
        "long_horizon",
        "overall",
    ]
    assert list(long.columns) == [
        "model",
        "instruction",
        "suite",
        "S_plan",
        "S_loc",
        "S_obj",
        "S_skill",
        "S_total",
        "Succ",
        "Loc_over_blind",
        "Move_ratio",
        "S_loc_prec",
        "n",
        "n_error",
        "missing_groups",
    ]


def test_a_suite_with_only_errors_leaves_overall_undefined(
    rec: Callable[..., EpisodeRecord],
) -> None:
    frame = records_frame(
        [
            rec("m", "base_manipulation", 0, "explicit", 80.0),
            rec("m", "long_horizon", 0, "explicit", None),
        ]
    )
    long = summary_long(frame)
    assert pd.isna(_row(long, "m", "explicit", "long_horizon").S_total)
    assert pd.isna(_row(long, "m", "explicit", "overall").S_total)


def test_wide_markdown_and_rich_layouts(frame: pd.DataFrame) -> None:
    long = summary_long(frame)
    wide = summary_wide(long)
    assert list(wide.index) == [
        ("m1", "explicit"),
        ("m1", "implicit"),
        ("m1", "both"),
        ("m2", "explicit"),
    ]
    assert wide.columns[0] == ("base_manipulation", "S_plan")
    assert wide.columns[-1] == ("overall", "S_loc_prec")  # the diagnostics follow ΔLoc
    assert wide.loc[("m1", "explicit"), ("overall", "S_total")] == pytest.approx(60.0)
    md = summary_markdown(long)
    header = md.splitlines()[0]
    assert header.startswith("| Model | Instr. | BM Plan | BM Loc | BM Obj | BM Skill | BM Tot")
    assert "| Overall Tot | Overall Succ | Overall ΔLoc |" in header
    assert "| m1 | explicit | 100.0 |" in md and "LH = Long-Horizon" in md
    assert len(summary_rich(long).columns) == 2 + 3 * 9  # 7 values and 2 diagnostics per group
    narrow = summary_rich(long, width=80)
    assert [c.header for c in narrow.columns][2:4] == ["Suite", "Plan"]
    assert narrow.row_count == len(long)


def test_write_summary_files_from_the_run_folder(
    tmp_path: Path, frame: pd.DataFrame, rec: Callable[..., EpisodeRecord]
) -> None:
    recs = [
        rec("m1", "base_manipulation", 0, "explicit", 100.0, succ=True),
        rec("m1", "semantic_understanding", 0, "explicit", 40.0),
    ]
    (tmp_path / "records.jsonl").write_text("".join(r.model_dump_json() + "\n" for r in recs))
    long = write_summary(tmp_path)
    csv = pd.read_csv(tmp_path / "summary.csv")
    assert list(csv.columns) == list(long.columns)
    overall = csv[csv.suite == "overall"].iloc[0]
    assert overall.S_total == pytest.approx(70.0) and overall.Succ == pytest.approx(50.0)
    assert "SU = Semantic Understanding" in (tmp_path / "summary.md").read_text()


def test_empty_frame_gives_an_empty_summary() -> None:
    long = summary_long(records_frame([]))
    assert long.empty and "No episodes" in summary_markdown(long)


def test_loc_over_blind_is_s_loc_minus_the_blind_floor_on_the_same_episode(
    make_scores: Callable[..., PlanScores],
) -> None:
    from vlm_bench import score_output
    from vlm_bench.backends.blind_planner import blind_plan
    from vlm_bench.episodes import get_episode
    from vlm_bench.types.plan import plan_to_json

    ep = get_episode("drawer_interaction", 3)
    gt = plan_to_json(ep.gt_plan)
    blind = json.dumps(plan_to_json(blind_plan(ep.task_id, ep.seed, ep.arm_steps())))
    floor = score_output(ep.task_id, ep.seed, blind).scores.s_loc
    record = EpisodeRecord(
        run_id="r",
        key="k",
        task_id=ep.task_id,
        suite=ep.suite,
        seed=ep.seed,
        variant="explicit",
        model="m",
        gt_plan=gt,
        scores=make_scores(100.0, 100.0, 100.0, 100.0, succ=True),
        status="ok",
    )
    row = records_frame([record]).iloc[0]
    assert row.S_loc_blind == pytest.approx(floor)
    assert row.Loc_over_blind == pytest.approx(100.0 - floor)
    assert floor < 100.0
