"""Demonstrations vary by seed, reproducibly, within the action space's speed bound."""

from __future__ import annotations

from vlm_bench.types.execution import ExecutorConfig, FlightConfig
from vlm_bench.vla.demos.variation import (
    MAX_SETPOINT_SPEED,
    DemoVariation,
    draw_variation,
    varied_config,
)


def test_draws_are_reproducible_and_differ_between_episodes() -> None:
    v = DemoVariation()
    a = draw_variation(v, "standard_pick_place", 10)
    assert a == draw_variation(v, "standard_pick_place", 10)
    others = {draw_variation(v, "standard_pick_place", s).speed for s in range(11, 31)}
    assert len(others) == 20 and a.speed not in others
    assert draw_variation(v, "verb_drop", 10) != a


def test_draws_stay_in_their_ranges() -> None:
    v = DemoVariation(speed=(0.2, 0.9))
    for seed in range(10, 60):
        d = draw_variation(v, "verb_drop", seed)
        assert 0.2 <= d.speed <= MAX_SETPOINT_SPEED  # 0.5 m/s: 2.5 cm per 50 ms step
        assert v.accel[0] <= d.accel <= v.accel[1] and v.stow_s[0] <= d.stow_s <= v.stow_s[1]


def test_no_variation_is_the_benchmark_executor() -> None:
    d = draw_variation(DemoVariation.none(), "verb_drop", 10)
    assert varied_config(d) == ExecutorConfig() and d.grasp_seed is None
    assert varied_config(d).flight == FlightConfig()
