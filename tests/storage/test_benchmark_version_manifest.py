"""The benchmark version in run manifests and config hashes; runs and rescores happen only in
the version this release evaluates."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import vlm_bench
from vlm_bench.storage import ConfigMismatchError, RunStore, read_manifest
from vlm_bench.storage.folder import RunPaths
from vlm_bench.types.benchmark_version import BENCHMARK_VERSION, BenchmarkVersionError
from vlm_bench.types.records import utc_now
from vlm_bench.types.run import DataHashes, RunConfig, RunManifest, config_differences, run_config
from vlm_bench.types.scores import ScoringConfig

RUN_V1 = Path(__file__).parent / "data" / "run_v1"


def _manifest(config: RunConfig, run_id: str = "run") -> RunManifest:
    return RunManifest(
        run_id=run_id,
        config=config,
        config_hash=config.config_hash(),
        backend="oracle",
        data=DataHashes(prompts="p", skills="s", ground_truth="g"),
        packages={},
        created=utc_now(),
    )


def test_every_new_manifest_records_this_releases_version() -> None:
    config = run_config(model="oracle")
    assert config.benchmark_version == BENCHMARK_VERSION == 3
    data = _manifest(config).model_dump(mode="json")
    assert data["config"]["benchmark_version"] == BENCHMARK_VERSION
    assert RunManifest.model_validate(data).config.benchmark_version == BENCHMARK_VERSION


def test_a_manifest_without_a_version_is_version_1_and_keeps_its_hash() -> None:
    old = read_manifest(RunPaths(RUN_V1))
    assert old.config.benchmark_version == 1
    assert "benchmark_version" not in old.config.hashed_fields()
    assert old.config.config_hash().startswith("2c27c5853f24cccf")  # as before versions


def test_version_1_configs_keep_their_hash_and_version_2_ones_change() -> None:
    # The default config of version 1 (S_loc by segment), as its manifests load: the hash the
    # last release of version 1 gave it.
    v1 = run_config(
        model="oracle",
        seeds=(0, 1),
        scoring=ScoringConfig(loc_alignment="segment"),
        benchmark_version=1,
    )
    assert v1.config_hash().startswith("c133db4028ad1d01")
    v2 = run_config(model="oracle", seeds=(0, 1))
    assert v2.hashed_fields()["benchmark_version"] == BENCHMARK_VERSION
    # The version and its S_loc default are all that differ between the two defaults.
    assert config_differences(v1, v2) == ["benchmark_version", "scoring.loc_alignment"]
    assert v2.short_hash() != v1.short_hash()


def test_a_version_1_run_is_not_resumed_by_this_release(tmp_path: Path) -> None:
    segment = ScoringConfig(loc_alignment="segment")
    old_config = run_config(model="oracle", scoring=segment, benchmark_version=1)
    RunStore.create_or_resume(
        tmp_path / "run", old_config, lambda r: _manifest(old_config, r)
    ).close()
    new_config = run_config(model="oracle", scoring=segment)
    with pytest.raises(ConfigMismatchError, match=r"benchmark version 1; this release evaluates"):
        RunStore.create_or_resume(tmp_path / "run", new_config, lambda r: _manifest(new_config, r))


def test_a_run_of_another_version_is_refused_before_a_folder_is_made(tmp_path: Path) -> None:
    with pytest.raises(BenchmarkVersionError, match=r"version 1, .* evaluates version 3") as info:
        vlm_bench.run(
            model="oracle", tasks=("tower_stacking",), benchmark_version=1, out=tmp_path / "r"
        )
    assert "\n" not in str(info.value)
    assert not (tmp_path / "r").exists()


def test_rescore_refuses_a_run_of_another_version(tmp_path: Path) -> None:
    copy = tmp_path / "run_v1"
    shutil.copytree(RUN_V1, copy)
    before = (copy / "records.jsonl").read_bytes()
    with pytest.raises(
        BenchmarkVersionError,
        match="run_v1 is benchmark version 1, from before versions were recorded",
    ):
        vlm_bench.rescore(copy)
    assert (copy / "records.jsonl").read_bytes() == before


def test_docs_say_what_changed_in_every_version() -> None:
    text = (Path(__file__).parents[2] / "docs" / "benchmark-versions.md").read_text()
    headings = [line for line in text.splitlines() if line.startswith("## Version ")]
    expected = [f"## Version {v}" for v in range(BENCHMARK_VERSION, 0, -1)]
    assert headings == expected
