"""Configuration hashes stay stable by one rule (types/config_hash.py): the hashes of existing
configurations, as main computed them before the rule replaced the hand-kept tables, are
unchanged; a perturbation kind added later enters a hash only when set."""

from __future__ import annotations

import pytest

from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.run import RunConfig
from vlm_bench.types.scores import ScoringConfig

CONFIGS = [
    dict(model="oracle"),
    dict(model="oracle", benchmark_version=1),
    dict(
        model="Qwen/Qwen2.5-VL-7B-Instruct",
        seeds=(0, 1, 2),
        instructions=("explicit",),
        resolution=224,
    ),
    dict(model="openai/gpt-4o", backend_args={"api_key": "x", "base_url": "http://h"}, k_shot=0),
    dict(model="rules", scene_as_text=True, images=False),
    dict(
        model="rules", scene_as_text=True, loop="closed", perturb=PerturbConfig(slip=0.3, bump=0.3)
    ),
    dict(model="rules", scene_as_text=True, loop="closed", perturb=PerturbConfig(slip=0.3)),
    dict(model="m", loop="closed", max_rounds=5, step_budget=20, history="images"),
    dict(model="m", perturb=PerturbConfig(bump=0.5), uav_noise=2.0),
    dict(model="m", generation=GenerationConfig(temperature=0.7, top_k=5, repetition_penalty=1.1)),
    dict(model="m", generation=GenerationConfig(constrained=True, batch_size=3)),
    dict(model="m", scoring=ScoringConfig(loc_alignment="order")),
    dict(model="m", scoring=ScoringConfig(loc_alignment="segment")),
    dict(model="m", execute=False, tasks=("standard_pick_place",)),
]

HASHES = [
    (
        "d6912f3e4f8b847e147ae09aafd296d4bd32160c1757477f6b2c65da12086690",
        "d6912f3e4f8b847e147ae09aafd296d4bd32160c1757477f6b2c65da12086690",
    ),
    (
        "511aa962b2ffe52b23c92d7c9dd48d777f404df2257fca7fbb9bd3b4d33529ba",
        "511aa962b2ffe52b23c92d7c9dd48d777f404df2257fca7fbb9bd3b4d33529ba",
    ),
    (
        "9f2cdf422a1223dfe7a7a070fefd452dec05722d21a9f76475263cb1a44c4361",
        "9f2cdf422a1223dfe7a7a070fefd452dec05722d21a9f76475263cb1a44c4361",
    ),
    (
        "66eceff985d745fc8e56d4944135105f75528dcfefa49a7032aab7af29234567",
        "2834913cf126463a0ad216d3045673dad07c61881cbfd6eccd2574be110bf248",
    ),
    (
        "e1abe3675ef292202e6fe9fe6be396874220e425f16c9cba36b748e63fd35c7d",
        "e1abe3675ef292202e6fe9fe6be396874220e425f16c9cba36b748e63fd35c7d",
    ),
    (
        "3117af303b327f52ea78773b993abc6281dd120f3fcec4477ff18e4cd563d6bb",
        "3117af303b327f52ea78773b993abc6281dd120f3fcec4477ff18e4cd563d6bb",
    ),
    (
        "3b1f5978d28db94ca066ea77183ac4800e7933196847faeae926cb4b96be2f3c",
        "3b1f5978d28db94ca066ea77183ac4800e7933196847faeae926cb4b96be2f3c",
    ),
    (
        "55835fe596a91d85d8f9018cd128afbcd5467bf96117659bd82057f9529ade33",
        "55835fe596a91d85d8f9018cd128afbcd5467bf96117659bd82057f9529ade33",
    ),
    (
        "2fd8a1aa3abf571df7fc7a13e4a4445544d843d8b2841de96b33fb3f0310ad6c",
        "2fd8a1aa3abf571df7fc7a13e4a4445544d843d8b2841de96b33fb3f0310ad6c",
    ),
    (
        "3455a549c43dbca10d55bddf1e89d49ca24428563c4270d6975e34246f3cfe17",
        "3455a549c43dbca10d55bddf1e89d49ca24428563c4270d6975e34246f3cfe17",
    ),
    (
        "4b1f9da4fd2ef9901f6071b0eada306c12448f1d4516c6c5d327042c63653420",
        "4b1f9da4fd2ef9901f6071b0eada306c12448f1d4516c6c5d327042c63653420",
    ),
    (
        "39f261ec9c20817a195de321e6501c822e3685a41a24640c9b5c2cbf34f8908e",
        "39f261ec9c20817a195de321e6501c822e3685a41a24640c9b5c2cbf34f8908e",
    ),
    (
        "2fdf90af160503f83f4c8966f3ee1b79ba193635cf6547a1115bfc538569c7b4",
        "2fdf90af160503f83f4c8966f3ee1b79ba193635cf6547a1115bfc538569c7b4",
    ),
    (
        "59c46424c4576d5fc36971ee9801f1d3f69a506d491eb7d1634cad83a007c30e",
        "59c46424c4576d5fc36971ee9801f1d3f69a506d491eb7d1634cad83a007c30e",
    ),
]
"""(config_hash(), config_hash(("base_url",))) of each, from the code before the rule (benchmark
version 2, which these configurations name: a new version is a new configuration)."""


@pytest.mark.parametrize(("fields", "hashes"), list(zip(CONFIGS, HASHES, strict=True)))
def test_existing_configurations_keep_their_hash(
    fields: dict[str, object], hashes: tuple[str, str]
) -> None:
    config = RunConfig(**{"benchmark_version": 2, **fields})  # type: ignore[arg-type]
    assert (config.config_hash(), config.config_hash(("base_url",))) == hashes


def test_a_kind_added_later_enters_the_hash_only_when_set() -> None:
    base = RunConfig(model="m", perturb=PerturbConfig(slip=0.3))
    same = RunConfig(model="m", perturb=PerturbConfig(slip=0.3, nudge=0.0))  # type: ignore[call-arg]
    other = RunConfig(model="m", perturb=PerturbConfig(slip=0.3, nudge=0.5))  # type: ignore[call-arg]
    assert same.config_hash() == base.config_hash() != other.config_hash()
    assert other.hashed_fields()["perturb"] == {"slip": 0.3, "bump": 0.0, "nudge": 0.5}
