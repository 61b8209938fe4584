"""Run folders on disk: manifest, append-only records, response cache, lock, snapshot cache."""

from vlm_bench.storage.folder import (
    ConfigMismatchError,
    NotARunError,
    RunLockedError,
    RunPaths,
    read_manifest,
)
from vlm_bench.storage.jsonl import JsonlWriter, iter_jsonl, repair_tail, torn_tail
from vlm_bench.storage.provenance import data_hashes, git_revision, package_versions
from vlm_bench.storage.record_reader import latest_records, read_records, read_responses
from vlm_bench.storage.snapshot_cache import SnapshotCache, default_snapshot_cache
from vlm_bench.storage.store import RunStore

__all__ = [
    "ConfigMismatchError",
    "JsonlWriter",
    "NotARunError",
    "RunLockedError",
    "RunPaths",
    "RunStore",
    "SnapshotCache",
    "data_hashes",
    "default_snapshot_cache",
    "git_revision",
    "iter_jsonl",
    "latest_records",
    "package_versions",
    "read_manifest",
    "read_records",
    "read_responses",
    "repair_tail",
    "torn_tail",
]
