"""Stated protocols: what a configuration is, what --protocol sets, what it refuses."""

from __future__ import annotations

import pytest

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.protocol import PROTOCOLS, ProtocolMark
from vlm_bench.types.protocol_match import (
    manifest_protocol,
    protocol_mark,
    protocol_of,
    with_protocol,
)
from vlm_bench.types.run import DataHashes, RunConfig, RunManifest

CLOSED = {"loop": "closed", "perturb": PerturbConfig(slip=0.3, bump=0.3)}


def test_the_defaults_over_protocol_seeds_are_the_paper_protocol() -> None:
    assert protocol_of(RunConfig(model="m", seeds=tuple(range(10)))) == "paper"
    # A subset of its episodes is still the paper protocol (a share of it).
    assert protocol_of(RunConfig(model="m", seeds=(0, 1), suite="long_horizon")) == "paper"
    assert protocol_of(RunConfig(model="m", **CLOSED)) == "closed"


@pytest.mark.parametrize(
    "fields",
    [
        {"resolution": 224},
        {"views": ("uav", "wrist")},
        {"k_shot": 0},
        {"object_list": False},
        {"scene_as_text": True},
        {"generation": GenerationConfig(temperature=0.7)},
        {"generation": GenerationConfig(constrained=True)},
        {"uav_noise": 2.0},
        {"seeds": (0, 12)},
        {"loop": "closed", "max_rounds": 2, "perturb": PerturbConfig(slip=0.3, bump=0.3)},
        {"loop": "closed"},  # closed loop without the protocol's perturbations
    ],
)
def test_any_scored_setting_off_the_protocols_is_custom(fields: dict[str, object]) -> None:
    assert protocol_of(RunConfig(model="m", **fields)) == "custom"  # type: ignore[arg-type]


def test_what_only_serves_the_model_leaves_the_protocol() -> None:
    config = RunConfig(
        model="openai/x",
        backend_args={"base_url": "http://127.0.0.1:1/v1", "api_key": "k"},
        generation=GenerationConfig(max_new_tokens=4096, batch_size=32),
        execute=False,
    )
    assert protocol_of(config) == "paper"


def test_with_protocol_fills_in_what_was_not_given() -> None:
    closed = with_protocol(RunConfig(model="m"), "closed")
    assert closed.seeds == tuple(range(10)) and closed.instructions == ("explicit", "implicit")
    assert closed.loop == "closed" and closed.max_rounds == 3
    assert closed.perturb == PerturbConfig(slip=0.3, bump=0.3)
    assert protocol_of(closed) == "closed"
    narrowed = with_protocol(RunConfig(model="m", seeds=(0, 1)), "paper", {"seeds"})
    assert narrowed.seeds == (0, 1) and protocol_of(narrowed) == "paper"
    assert with_protocol(RunConfig(model="m", k_shot=0), "custom").k_shot == 0


@pytest.mark.parametrize(
    ("fields", "given", "message"),
    [
        ({"resolution": 224}, {"resolution"}, "--protocol paper sets --resolution to 448"),
        ({"seeds": (3, 11)}, {"seeds"}, "--protocol paper takes seeds within 0-9"),
        ({"loop": "closed"}, {"loop"}, "--protocol paper sets --loop to open"),
        ({"uav_noise": 1.0}, {"uav_noise"}, "--protocol paper sets --uav-noise to 0.0"),
    ],
)
def test_with_protocol_refuses_a_given_option_it_fixes(
    fields: dict[str, object], given: set[str], message: str
) -> None:
    with pytest.raises(ConfigError, match=message):
        with_protocol(RunConfig(model="m", **fields), "paper", given)  # type: ignore[arg-type]


def test_an_unknown_protocol_lists_the_valid_names() -> None:
    with pytest.raises(UnknownNameError, match="valid: closed, custom, paper"):
        with_protocol(RunConfig(model="m"), "papers")


def test_protocol_mark_counts_the_share_of_the_protocol() -> None:
    mark = protocol_mark(RunConfig(model="m", seeds=(0, 1)), 240, 60)
    assert (mark.episodes, mark.protocol_episodes) == (240, 1200)
    assert mark.fraction == pytest.approx(0.2) and not mark.complete
    assert mark.label() == "paper (240 of 1,200 episodes, 20%)"
    full = protocol_mark(RunConfig(model="m", seeds=PROTOCOLS["paper"].seeds), 1200, 60)
    assert full.complete and full.label() == "paper"
    custom = protocol_mark(RunConfig(model="m", resolution=64), 8, 60)
    assert custom.label() == "custom" and custom.fraction is None


def test_a_manifest_from_before_protocols_loads_and_gets_its_protocol() -> None:
    config = RunConfig(model="m", seeds=(0, 1))
    manifest = RunManifest(
        run_id="r",
        config=config,
        config_hash=config.config_hash(),
        backend="oracle",
        data=DataHashes(prompts="p", skills="s", ground_truth="g"),
        packages={},
        created="2026-01-01T00:00:00Z",  # type: ignore[arg-type]
    )
    old = manifest.model_dump(mode="json")
    del old["protocol"]
    loaded = RunManifest.model_validate(old)
    assert loaded.protocol is None
    assert manifest_protocol(loaded) == ProtocolMark(name="paper")


def test_closed_refuses_no_execute_in_one_line() -> None:
    with pytest.raises(ConfigError, match="loop closed needs execute"):
        with_protocol(RunConfig(model="m", execute=False), "closed", {"execute"})
