"""Run folders: durable JSONL, torn-line repair, the writer lock, config checks, caches."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from vlm_bench.backends import operational_args
from vlm_bench.errors import DataFileError
from vlm_bench.storage import (
    ConfigMismatchError,
    JsonlWriter,
    NotARunError,
    RunLockedError,
    RunStore,
    SnapshotCache,
    iter_jsonl,
    read_manifest,
    repair_tail,
)
from vlm_bench.storage.folder import RunPaths
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.records import CachedResponse, EpisodeRecord, utc_now
from vlm_bench.types.run import DataHashes, RunConfig, RunManifest, run_config
from vlm_bench.types.scores import ScoringConfig


def _manifest_for(config: RunConfig):  # type: ignore[no-untyped-def]
    def build(run_id: str) -> RunManifest:
        return RunManifest(
            run_id=run_id,
            config=config.redacted(),
            config_hash=config.config_hash(operational_args(config.model)),
            operational_args=tuple(sorted(operational_args(config.model))),
            backend="oracle",
            data=DataHashes(prompts="p", skills="s", ground_truth="g"),
            packages={},
            created=utc_now(),
        )

    return build


def _record(key: str, status: str = "ok") -> EpisodeRecord:
    task, seed, variant = key.split("/")
    return EpisodeRecord(
        run_id="r",
        key=key,
        task_id=task,
        suite="base_manipulation",
        seed=int(seed),
        variant=variant,
        model="m",
        status=status,
        backend_error="boom" if status == "error" else None,
    )


def test_jsonl_torn_last_line_is_skipped_then_repaired(tmp_path: Path) -> None:
    path = tmp_path / "x.jsonl"
    with JsonlWriter(path) as writer:
        writer.append({"a": 1})
        writer.append({"a": 2})
    with path.open("ab") as fh:
        fh.write(b'{"a": 3, "trunc')  # a crash mid-write
    assert [obj["a"] for _, obj in iter_jsonl(path)] == [1, 2]
    assert repair_tail(path) == len(b'{"a": 3, "trunc')
    assert path.read_bytes() == b'{"a": 1}\n{"a": 2}\n'
    with JsonlWriter(path) as writer:  # appending after repair yields valid JSONL
        writer.append({"a": 4})
    assert [obj["a"] for _, obj in iter_jsonl(path)] == [1, 2, 4]
    assert repair_tail(path) == 0


def test_jsonl_torn_only_line_is_removed(tmp_path: Path) -> None:
    path = tmp_path / "x.jsonl"
    path.write_bytes(b'{"half": ')
    assert list(iter_jsonl(path)) == []
    assert repair_tail(path) == 9
    assert path.read_bytes() == b""


def test_jsonl_corrupted_middle_line_names_file_and_line(tmp_path: Path) -> None:
    path = tmp_path / "x.jsonl"
    path.write_text('{"a": 1}\nnot json\n{"a": 2}\n')
    with pytest.raises(DataFileError, match=r"x\.jsonl: line 2: invalid JSON"):
        list(iter_jsonl(path))


def test_writer_repairs_tail_on_open(tmp_path: Path) -> None:
    path = tmp_path / "x.jsonl"
    path.write_bytes(b'{"a": 1}\n{"a": 2')
    JsonlWriter(path).close()
    assert path.read_bytes() == b'{"a": 1}\n'


def test_store_resumes_and_latest_record_wins(tmp_path: Path) -> None:
    config = RunConfig(model="oracle", seeds=(0, 1))
    root = tmp_path / "run"
    with RunStore.create_or_resume(root, config, _manifest_for(config)) as store:
        store.append_record(_record("t/0/explicit", "error"))
        store.append_record(_record("t/1/explicit"))
        store.append_response(CachedResponse(key="t/1/explicit", prompt_hash="h", text="[]"))
        assert not store.is_done("t/0/explicit")
    with (root / "records.jsonl").open("ab") as fh:
        fh.write(b'{"schema_version": 1, "run_id": "r", "key": "t/0/ex')  # torn
    with RunStore.create_or_resume(root, config, _manifest_for(config)) as store:
        assert store.repaired_bytes > 0
        assert store.is_done("t/1/explicit") and not store.is_done("t/0/explicit")
        assert store.cached_response("t/1/explicit", "h") is not None
        assert store.cached_response("t/1/explicit", "other") is None
        store.append_record(_record("t/0/explicit"))
    with RunStore.open_existing(root) as store:
        assert store.is_done("t/0/explicit")
        assert list(store.records) == ["t/0/explicit", "t/1/explicit"]
    assert len((root / "records.jsonl").read_text().splitlines()) == 3


def test_mismatched_config_is_refused_naming_fields(tmp_path: Path) -> None:
    config = RunConfig(model="oracle", seeds=(0, 1))
    root = tmp_path / "run"
    RunStore.create_or_resume(root, config, _manifest_for(config)).close()
    other = config.model_copy(
        update={
            "seeds": (0, 1, 2),
            "generation": GenerationConfig(max_new_tokens=64),
        }
    )
    with pytest.raises(ConfigMismatchError) as info:
        RunStore.create_or_resume(root, other, _manifest_for(other))
    message = str(info.value)
    assert "\n" not in message
    assert "generation.max_new_tokens" in message and "seeds" in message
    assert "resolution" not in message
    # The lock was released: the original config resumes fine.
    RunStore.create_or_resume(root, config, _manifest_for(config)).close()


def test_batch_size_and_secrets_do_not_change_the_config(tmp_path: Path) -> None:
    base = RunConfig(model="openai/x", backend_args={"api_key": "sk-1", "base_url": "http://a"})
    fast = base.model_copy(
        update={
            "generation": GenerationConfig(batch_size=32),
            "backend_args": {"api_key": "sk-2", "base_url": "http://a", "concurrency": "16"},
        }
    )
    operational = operational_args("openai/x")
    assert base.config_hash(operational) == fast.config_hash(operational)
    # The server URL is not operational: another server may serve other weights.
    moved = base.model_copy(update={"backend_args": {"api_key": "sk-1", "base_url": "http://b"}})
    assert moved.config_hash(operational) != base.config_hash(operational)
    root = tmp_path / "run"
    RunStore.create_or_resume(root, base, _manifest_for(base)).close()
    text = (root / "manifest.json").read_text()
    assert "sk-1" not in text and "***" in text
    RunStore.create_or_resume(root, fast, _manifest_for(fast)).close()  # resumable


def test_config_hash_is_canonical_and_sensitive() -> None:
    a = run_config(model="m", seeds=(3, 1, 1), instructions=("implicit", "explicit"))
    b = run_config(model="m", seeds=(1, 3), instructions=("explicit", "implicit"))
    assert a.config_hash() == b.config_hash() and len(a.short_hash()) == 8
    changes = [
        {"resolution": 224},
        {"views": ("uav",)},
        {"k_shot": 0},
        {"object_list": False},
        {"scoring": ScoringConfig(alpha=0.7)},
        {"model": "n"},
        {"suite": "long_horizon"},
        {"generation": GenerationConfig(constrained=True)},
        {"execute": False},
        {"uav_noise": 1.5},
    ]
    hashes = {run_config(**{**b.model_dump(), **c}).config_hash() for c in changes}
    assert len(hashes) == len(changes) and b.config_hash() not in hashes


def test_configs_of_earlier_releases_keep_their_hash() -> None:
    # Before plan execution existed every run had execute=False and no uav_noise; such a
    # config still hashes as it did then (pinned), so its default run folder is unchanged.
    # S_loc was paired by order then (loc_alignment="order"), in benchmark version 1.
    old = run_config(
        model="oracle",
        seeds=(0, 1),
        execute=False,
        scoring=ScoringConfig(loc_alignment="order"),
        benchmark_version=1,
    )
    assert old.config_hash().startswith("e4a433ac133d1e2a")
    assert "uav_noise" not in old.hashed_fields()
    assert "loc_alignment" not in old.hashed_fields()["scoring"]
    assert "benchmark_version" not in old.hashed_fields()
    assert run_config(model="oracle", seeds=(0, 1)).short_hash() != old.short_hash()


def test_second_writer_is_refused(tmp_path: Path) -> None:
    config = RunConfig(model="oracle")
    root = tmp_path / "run"
    first = RunStore.create_or_resume(root, config, _manifest_for(config))
    try:
        with pytest.raises(RunLockedError, match="being written by another vlm-bench process"):
            RunStore.create_or_resume(root, config, _manifest_for(config))
        with pytest.raises(RunLockedError):
            RunStore.open_existing(root)
    finally:
        first.close()
    RunStore.open_existing(root).close()


def test_lock_held_by_another_process_and_freed_when_it_dies(tmp_path: Path) -> None:
    root = tmp_path / "run"
    root.mkdir()
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            textwrap.dedent(f"""
            import sys, time
            from filelock import FileLock
            lock = FileLock({str(root / ".lock")!r}, timeout=0)
            lock.acquire()
            print('held', flush=True)
            time.sleep(60)
        """),
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        config = RunConfig(model="oracle")
        with pytest.raises(RunLockedError):
            RunStore.create_or_resume(root, config, _manifest_for(config))
    finally:
        holder.kill()
        holder.wait()
    RunStore.create_or_resume(
        root, RunConfig(model="oracle"), _manifest_for(RunConfig(model="oracle"))
    ).close()


def test_missing_or_corrupted_manifest(tmp_path: Path) -> None:
    with pytest.raises(NotARunError, match="not a vlm-bench run folder"):
        RunStore.open_existing(tmp_path)
    (tmp_path / "manifest.json").write_text(json.dumps({"run_id": "x"}))
    with pytest.raises(DataFileError, match=r"manifest\.json: config"):
        read_manifest(RunPaths(tmp_path))


def test_snapshot_cache_round_trip(tmp_path: Path) -> None:
    cache = SnapshotCache(tmp_path / "snap")
    key = "ab" * 32
    assert cache.get(key, "uav") is None
    cache.put(key, "uav", b"\x89PNG...")
    assert cache.get(key, "uav") == b"\x89PNG..."
    assert (cache.hits, cache.misses) == (1, 1)
    with pytest.raises(ValueError, match="bad snapshot cache key"):
        cache.get("../etc", "uav")


def test_a_folder_holding_other_files_is_not_taken_over(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    config = RunConfig(model="oracle")
    with pytest.raises(NotARunError, match="not empty and holds no vlm-bench run"):
        RunStore.create_or_resume(tmp_path, config, _manifest_for(config))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_a_manifest_from_before_loc_alignment_loads_as_order_and_keeps_its_hash() -> None:
    new = run_config(model="oracle", seeds=(0, 1))
    assert new.scoring.loc_alignment == "content"
    data = _manifest_for(new)("run").model_dump(mode="json")
    del data["config"]["scoring"]["loc_alignment"]  # as a manifest of an earlier release
    old = RunManifest.model_validate(data)
    assert old.config.scoring.loc_alignment == "order"
    assert "loc_alignment" not in old.config.hashed_fields()["scoring"]
    assert old.config.config_hash() != new.config_hash()


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_disk_names_the_file() -> None:
    writer = JsonlWriter(Path("/dev/full"))  # every write fails with ENOSPC
    try:
        with pytest.raises(OSError, match="No space left") as info:
            writer.append({"a": 1})
        assert info.value.filename == "/dev/full"
    finally:
        writer.close()
