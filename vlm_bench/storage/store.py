"""An open run folder: locked, manifest checked, torn lines repaired, records and cache loaded."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterable
from pathlib import Path
from types import TracebackType
from typing import Self

from filelock import FileLock

from vlm_bench.storage.folder import (
    NotARunError,
    RunPaths,
    acquire_lock,
    check_compatible,
    read_manifest,
    write_manifest,
)
from vlm_bench.storage.jsonl import JsonlWriter, repair_tail, write_jsonl_atomic
from vlm_bench.storage.record_reader import latest_records, read_responses
from vlm_bench.types.records import CachedResponse, EpisodeRecord
from vlm_bench.types.run import RunConfig, RunManifest


class RunStore:
    """The single writer of a run folder (see :mod:`vlm_bench.storage.folder` for the layout).

    Use :meth:`create_or_resume` to run and :meth:`open_existing` to rescore. Appends are
    durable per line; :meth:`close` (or leaving the ``with`` block) releases the lock.
    """

    def __init__(
        self, paths: RunPaths, lock: FileLock, manifest: RunManifest, *, created: bool = False
    ) -> None:
        self.paths = paths
        self.manifest = manifest
        self._lock = lock
        self.created = created
        """This store wrote the manifest: the run started here (see :meth:`__exit__`)."""
        self._made_root = False
        self.torn_record_bytes = repair_tail(paths.records)
        """Bytes of a torn last record line cut off at opening (a crash mid-write)."""
        self.repaired_bytes = self.torn_record_bytes + repair_tail(paths.responses)
        self.records: dict[str, EpisodeRecord] = {r.key: r for r in latest_records(paths.records)}
        self.responses: dict[tuple[str, str], CachedResponse] = read_responses(paths.responses)
        self._record_writer: JsonlWriter | None = None
        self._response_writer: JsonlWriter | None = None

    @classmethod
    def create_or_resume(
        cls, root: Path, config: RunConfig, make_manifest: Callable[[str], RunManifest]
    ) -> Self:
        """Open ``root`` for writing: create the run, or resume it if the config matches.

        Args:
            root: The run folder (created if missing).
            config: The run's configuration.
            make_manifest: Builds the manifest for a run id (the folder name).

        Raises:
            NotARunError: ``root`` holds other files but no run.
            RunLockedError: Another process writes the folder.
            ConfigMismatchError: The folder holds a run with another config (names the fields).
            DataFileError: A corrupted manifest or record file (names file and field).
        """
        paths = RunPaths(root)
        if (
            root.is_dir()
            and not paths.manifest.exists()
            and any(p.name != paths.lock.name for p in root.iterdir())
        ):
            raise NotARunError(
                f"{root} is not empty and holds no vlm-bench run (no "
                "manifest.json); choose a new or empty folder"
            )
        made_root = not root.exists()
        lock = acquire_lock(paths)
        try:
            manifest = make_manifest(paths.run_id)
            created = not paths.manifest.exists()
            if created:
                write_manifest(paths, manifest)
            else:
                stored = read_manifest(paths)
                check_compatible(paths, stored, config, manifest)
                manifest = stored
            store = cls(paths, lock, manifest, created=created)
        except BaseException:
            lock.release()
            if made_root:
                _remove_start(paths, made_root)
            raise
        store._made_root = made_root
        return store

    @classmethod
    def open_existing(cls, root: Path) -> Self:
        """Open an existing run folder for rewriting (rescore).

        Raises:
            NotARunError: No manifest in ``root``.
            RunLockedError: Another process writes the folder.
        """
        paths = RunPaths(root)
        manifest = read_manifest(paths)
        lock = acquire_lock(paths)
        try:
            return cls(paths, lock, manifest)
        except BaseException:
            lock.release()
            raise

    def is_done(self, key: str) -> bool:
        """True when the episode has a record the model answered (error records are retried)."""
        record = self.records.get(key)
        return record is not None and record.ok

    def cached_response(self, key: str, prompt_hash: str) -> CachedResponse | None:
        """The cached answer to this exact prompt for this episode, if any."""
        return self.responses.get((key, prompt_hash))

    def append_response(self, response: CachedResponse) -> None:
        """Add a model answer to the response cache (durable before its record is written)."""
        if self._response_writer is None:
            self._response_writer = JsonlWriter(self.paths.responses)
        self._response_writer.append(response.model_dump_json())
        self.responses[(response.key, response.prompt_hash)] = response

    def append_record(self, record: EpisodeRecord) -> None:
        """Append one episode record (flushed and fsynced)."""
        if self._record_writer is None:
            self._record_writer = JsonlWriter(self.paths.records)
        self._record_writer.append(record.model_dump_json())
        self.records[record.key] = record

    def rewrite_records(self, records: Iterable[EpisodeRecord]) -> None:
        """Replace ``records.jsonl`` atomically (rescore); one line per key."""
        if self._record_writer is not None:
            self._record_writer.close()
            self._record_writer = None
        rows = list(records)
        write_jsonl_atomic(self.paths.records, [r.model_dump_json() for r in rows])
        self.records = {r.key: r for r in rows}

    def close(self) -> None:
        """Close the files and release the lock. Idempotent."""
        for writer in (self._record_writer, self._response_writer):
            if writer is not None:
                writer.close()
        self._record_writer = self._response_writer = None
        if self._lock.is_locked:
            self._lock.release()

    def __enter__(self) -> Self:
        return self

    def discard_start(self) -> bool:
        """Close, and remove the run this store started if no model answer or record was
        written: a failed start leaves no folder behind (a retry starts clean, even with other
        options). Returns True when the run was removed."""
        self.close()
        if not self.created or any(
            p.exists() and p.stat().st_size > 0 for p in (self.paths.records, self.paths.responses)
        ):
            return False
        _remove_start(self.paths, self._made_root)
        return True

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if exc_type is None:
            self.close()
        else:
            self.discard_start()


def _remove_start(paths: RunPaths, made_root: bool) -> None:
    """Delete what starting a run writes (manifest, empty record files, lock), and the folder
    when the start created it and nothing else is in it."""
    for path in (paths.manifest, paths.records, paths.responses, paths.lock):
        path.unlink(missing_ok=True)
    if made_root:
        with contextlib.suppress(OSError):  # something else was put there meanwhile: keep it
            paths.root.rmdir()
