"""Statistics: exact sign test, task-clustered bootstrap, paired comparisons, tiers, codes."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pandas as pd
import pytest

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.report import (
    bootstrap_cis,
    error_code_frequencies,
    failure_code_frequencies,
    failure_code_table,
    loc_over_blind_run,
    paired_comparison,
    paired_table,
    parse_tier_rates,
    records_frame,
    sign_test,
    summary_long,
)
from vlm_bench.report.groups import Grouping
from vlm_bench.types.execution import ExecutionSummary, FailureCode
from vlm_bench.types.records import EpisodeRecord

Make = Callable[..., EpisodeRecord]
ONE = Grouping(name="one", column="_g", order=("g",), titles={"g": "G"}, short={"g": "G"})


def synthetic(n_tasks: int, seeds: int = 2) -> pd.DataFrame:
    """One group; task i's episodes score (37 i mod 100) ± 5 by seed: spread between tasks."""
    rows = [
        {
            "model": "m", "run": "r", "task_id": f"t{i}", "seed": s, "instruction": "explicit",
            "status": "ok", "_g": "g", "S_total": float((37 * i) % 100 + (5 - 10 * s) * (i % 2)),
        }
        for i in range(n_tasks)
        for s in range(seeds)
    ]  # fmt: skip
    return pd.DataFrame(rows)


def _overall(cis: pd.DataFrame, column: str = "_g") -> pd.Series:
    return cis[(cis[column] == "overall") & (cis.metric == "S_total")].iloc[0]


@pytest.mark.parametrize(
    ("better", "worse", "p"),
    [(3, 0, 0.25), (7, 2, 92 / 512), (0, 12, 2 / 4096), (10, 10, 1.0), (0, 0, 1.0), (1, 0, 1.0)],
)
def test_sign_test_exact_values(better: int, worse: int, p: float) -> None:
    # (7, 2): 2 · (C(9,0) + C(9,1) + C(9,2)) / 2^9 = 2 · 46 / 512.
    assert sign_test(better, worse) == pytest.approx(p, rel=1e-12)
    assert sign_test(worse, better) == pytest.approx(p, rel=1e-12)


def test_sign_test_agrees_with_scipy() -> None:
    stats = pytest.importorskip("scipy.stats")
    for better, worse in [(5, 1), (13, 4), (20, 20), (31, 9), (2, 40)]:
        expected = stats.binomtest(better, better + worse).pvalue
        assert sign_test(better, worse) == pytest.approx(expected, rel=1e-9)


def test_bootstrap_is_reproducible_with_a_seed() -> None:
    frame = synthetic(12)
    a = bootstrap_cis(frame, grouping=ONE, metrics=("S_total",), n_boot=500, seed=3)
    b = bootstrap_cis(frame, grouping=ONE, metrics=("S_total",), n_boot=500, seed=3)
    c = bootstrap_cis(frame, grouping=ONE, metrics=("S_total",), n_boot=500, seed=4)
    pd.testing.assert_frame_equal(a, b)
    assert (_overall(a).lo, _overall(a).hi) != (_overall(c).lo, _overall(c).hi)


def test_bootstrap_interval_shrinks_as_episodes_grow() -> None:
    widths = []
    for n_tasks in (5, 20, 80):
        row = _overall(bootstrap_cis(synthetic(n_tasks), grouping=ONE, metrics=("S_total",)))
        assert row.lo <= row.value <= row.hi
        widths.append(row.hi - row.lo)
    assert widths[0] > widths[1] > widths[2] > 0
    # Clustered by task: about 1/sqrt(tasks), so four times the tasks halve the width.
    assert widths[1] / widths[2] == pytest.approx(2.0, rel=0.3)


def test_bootstrap_two_tasks_hand_computed() -> None:
    # Tasks score 0 and 100: a replicate draws two tasks, mean 0, 50 or 100 with odds 1:2:1,
    # so the 95 % interval is [0, 100] around the value 50.
    frame = synthetic(2, seeds=1)
    frame["S_total"] = [0.0, 100.0]
    row = _overall(bootstrap_cis(frame, grouping=ONE, metrics=("S_total",), n_boot=4000))
    assert (row.value, row.lo, row.hi, row.n, row.n_tasks) == (50.0, 0.0, 100.0, 2, 2)


def test_bootstrap_values_are_the_table_values(make_record: Make) -> None:
    recs = [
        make_record("m", "standard_pick_place", 0, "explicit", 100.0, succ=True),
        make_record("m", "color_distractor_green", 0, "explicit", 40.0),
        make_record("m", "tower_stacking", 0, "explicit", 20.0),
        make_record("m", "drawer_interaction", 0, "explicit", 60.0),
        make_record("m", "standard_pick_place", 0, "implicit", 50.0),
        make_record("m", "tower_stacking", 0, "implicit", 10.0),
        make_record("m", "drawer_interaction", 0, "implicit", None),
    ]
    frame = records_frame(recs)
    long = summary_long(frame).set_index(["instruction", "suite"])
    cis = bootstrap_cis(frame, n_boot=200)
    for row in cis.itertuples():
        metric = row.metric
        assert row.value == pytest.approx(long.loc[(row.instruction, row.suite), metric])
    # Base has two tasks (an interval), long-horizon explicit too; implicit LH has one answered
    # task: no interval there, nor in the overall values built on it.
    both = cis[(cis.instruction == "both") & (cis.suite == "overall") & (cis.metric == "S_total")]
    assert both.iloc[0].value == pytest.approx(((70 + 50) / 2 + (40 + 10) / 2) / 2)  # 42.5
    lh_implicit = cis[(cis.instruction == "implicit") & (cis.suite == "long_horizon")]
    assert lh_implicit.lo.isna().all() and lh_implicit.hi.isna().all()
    explicit = cis[(cis.instruction == "explicit") & (cis.suite == "overall")]
    assert explicit.lo.notna().all()


def test_paired_comparison_of_a_run_with_itself_is_zero(make_record: Make) -> None:
    recs = [
        make_record("m", t, s, v, float(10 * s + len(t) % 7 + (v == "implicit")), run=run)
        for run in ("a", "b")
        for t in ("standard_pick_place", "color_distractor_green", "tower_stacking",
                  "drawer_interaction")
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]  # fmt: skip
    frame = records_frame(recs).assign(run=lambda f: f.run_id)
    for metric in ("S_total", "Succ", "S_loc"):
        same = paired_comparison(frame, "a", "a", metric)
        assert same.diff == 0.0 and same.lo <= 0.0 <= same.hi
        assert (same.n, same.n_tasks, same.n_tied, same.p_sign) == (16, 4, 4, 1.0)
    twin = paired_comparison(frame, "a", "b")  # identical scores in another run
    assert twin.diff == 0.0 and twin.lo == 0.0 == twin.hi


def test_paired_comparison_hand_computed(make_record: Make) -> None:
    tasks = ("standard_pick_place", "color_distractor_green", "tower_stacking",
             "drawer_interaction")  # fmt: skip
    recs = [make_record("b", t, 0, "explicit", 50.0) for t in tasks]
    recs += [make_record("a", t, 0, "explicit", 60.0) for t in tasks[:3]]  # one episode missing
    recs += [make_record("a", tasks[3], 1, "explicit", 0.0)]  # seed 1: not common
    frame = records_frame(recs).assign(run=lambda f: f.run_id)
    result = paired_comparison(frame, "a", "b", "S_total")
    assert (result.n, result.n_tasks, result.n_better, result.n_worse) == (3, 3, 3, 0)
    assert result.diff == pytest.approx(10.0)  # every common episode differs by 10
    assert result.p_sign == pytest.approx(0.25)
    # Long-horizon has one common task: resampling cannot vary it, so no interval.
    assert math.isnan(result.lo) and math.isnan(result.hi)


def test_the_sign_test_counts_tasks_not_episodes(make_record: Make) -> None:
    """5 tasks × 2 seeds × 2 instructions, A better on all 20 episodes: over episodes the sign
    test would give 2 / 2^20 < 0.001; a task's episodes are one unit, so p = 2 / 2^5."""
    tasks = ("standard_pick_place", "color_distractor_green", "target_color_yellow",
             "tower_stacking", "drawer_interaction")  # fmt: skip
    recs = [
        make_record(run, t, s, v, score, run=run)
        for run, score in (("a", 80.0), ("b", 40.0))
        for t in tasks
        for s in (0, 1)
        for v in ("explicit", "implicit")
    ]
    frame = records_frame(recs).assign(run=lambda f: f.run_id)
    result = paired_comparison(frame, "a", "b", "S_total", n_boot=100)
    assert (result.n, result.n_tasks, result.n_better, result.n_worse) == (20, 5, 5, 0)
    assert result.p_sign == pytest.approx(0.0625)
    from vlm_bench.report.sections import pair_section

    row = pair_section(paired_table(frame, "b", n_boot=100), "t", "c").frame.iloc[0]
    assert row["sign p (tasks)"] == "0.062 (5)" and row["tasks A>B/A<B/="] == "5/0/0"


def test_paired_comparison_errors(make_record: Make) -> None:
    frame = records_frame([make_record("a", "standard_pick_place", 0, "explicit", 1.0)])
    frame["run"] = frame["run_id"]
    with pytest.raises(UnknownNameError, match="valid: a"):
        paired_comparison(frame, "a", "nope")
    with pytest.raises(ConfigError, match="no episode column"):
        paired_comparison(frame, "a", "a", "S_nothing")
    with pytest.raises(ConfigError, match="not a numeric"):
        paired_comparison(frame, "a", "a", "task_id")


def test_parse_tiers_and_error_codes_hand_computed(make_record: Make) -> None:
    recs = [
        make_record("m", "standard_pick_place", 0, "explicit", 100.0, tier="valid"),
        make_record("m", "standard_pick_place", 0, "implicit", 50.0, tier="repaired",
                    tags=("wrong_direction",)),
        make_record("m", "tower_stacking", 0, "explicit", 0.0, tier="invalid",
                    tags=("no_json", "no_plan")),
        make_record("m", "tower_stacking", 0, "implicit", 40.0, tags=("wrong_direction",)),
        make_record("m", "tower_stacking", 1, "implicit", None),
        make_record("n", "tower_stacking", 0, "implicit", 40.0),
    ]  # fmt: skip
    frame = records_frame(recs)
    tiers = parse_tier_rates(frame).set_index("model")
    assert tiers.loc["m", ["valid", "repaired", "invalid"]].tolist() == [50.0, 25.0, 25.0]
    assert (tiers.loc["m", "n"], tiers.loc["m", "n_error"]) == (4, 1)
    assert tiers.loc["n", "valid"] == 100.0
    codes = error_code_frequencies(frame)
    m = codes[codes.model == "m"].set_index("code")
    assert list(m.index) == ["wrong_direction", "no_json", "no_plan"]
    assert m.loc["wrong_direction", "count"] == 2 and m.loc["wrong_direction", "share"] == 50.0
    assert m.loc["no_plan", "share"] == 25.0
    assert not (codes.model == "n").any()


def test_execution_failure_codes_per_system(
    make_record: Make, make_execution: Callable[..., ExecutionSummary]
) -> None:
    """Shares are of the answered episodes that were to be executed: 4 for m (2 executions fail
    out of reach, 1 answer held no plan, 1 succeeds); the backend error is not counted."""
    crash = make_execution(False, 0.0).model_copy(
        update={"failure_code": FailureCode.EXECUTOR_CRASH, "failure_reason": "executor raised"}
    )
    recs = [
        make_record("m", "standard_pick_place", 0, "explicit", 90.0,
                    executed=make_execution(False, 50.0)),
        make_record("m", "standard_pick_place", 0, "implicit", 90.0,
                    executed=make_execution(False, 0.0)),
        make_record("m", "tower_stacking", 0, "explicit", 10.0, executed=None),
        make_record("m", "tower_stacking", 0, "implicit", 100.0,
                    executed=make_execution(True, 100.0)),
        make_record("m", "tower_stacking", 1, "implicit", None),
        make_record("n", "tower_stacking", 0, "implicit", 40.0, executed=crash),
    ]  # fmt: skip
    frame = records_frame(recs, {"m": True, "n": True})
    assert frame["exec_failure_code"].fillna("-").tolist() == [
        "out_of_reach", "out_of_reach", "no_plan", "-", "-", "executor_crash",
    ]  # fmt: skip
    long = failure_code_frequencies(frame).set_index(["model", "code"])
    assert long.loc[("m", "out_of_reach"), "count"] == 2
    assert long.loc[("m", "out_of_reach"), "share"] == 50.0
    assert long.loc[("m", "no_plan"), "share"] == 25.0
    assert long.loc[("n", "executor_crash"), "share"] == 100.0
    wide = failure_code_table(frame).set_index("model")
    assert list(wide.columns) == ["out_of_reach", "executor_crash", "no_plan"]  # ties by name
    assert wide.loc["n"].tolist() == [0.0, 100.0, 0.0]
    assert failure_code_table(records_frame(recs, {"m": False, "n": False})).empty


def test_loc_above_a_blind_run(make_record: Make) -> None:
    tasks = ("standard_pick_place", "color_distractor_green")
    recs = [make_record("blind", t, s, "explicit", 80.0, loc=30.0) for t in tasks for s in (0, 1)]
    recs += [make_record("vlm", t, s, "explicit", 80.0, loc=50.0 + 10 * s) for t in tasks
             for s in (0, 1)]  # fmt: skip
    frame = records_frame(recs).assign(run=lambda f: f.run_id)
    table = loc_over_blind_run(frame, n_boot=300).set_index("a")
    assert list(table.index) == ["vlm"] and table.loc["vlm", "b"] == "blind"
    assert table.loc["vlm", "diff"] == pytest.approx(25.0)  # (20 + 30) / 2
    assert table.loc["vlm", "n_better"] == 2  # tasks, not episodes
    assert 20.0 <= table.loc["vlm", "lo"] <= 25.0 <= table.loc["vlm", "hi"] <= 30.0
    assert loc_over_blind_run(frame[frame.model != "blind"]).empty


def test_multiplicities_resample_within_strata() -> None:
    from vlm_bench.report.bootstrap import multiplicities

    strata = np.array(["a", "a", "a", "b", "b"])
    w = multiplicities(strata, 50, np.random.default_rng(0))
    assert w.shape == (50, 5)
    assert (w[:, :3].sum(axis=1) == 3).all() and (w[:, 3:].sum(axis=1) == 2).all()


def test_systems_of_several_columns_are_named_with_slashes(make_record: Make) -> None:
    from vlm_bench.report.paired import find_system

    frame = records_frame([make_record("m", "standard_pick_place", 0, "explicit", 1.0)])
    frame["res"] = 448
    assert find_system(frame, ["model", "res"], "m/448") == ("m", 448)
    assert find_system(frame, ["model", "res"], ("m", 448)) == ("m", 448)
    with pytest.raises(UnknownNameError, match="valid: m/448"):
        find_system(frame, ["model", "res"], "m/224")
