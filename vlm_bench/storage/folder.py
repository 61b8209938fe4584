"""Run folders: layout, the writer lock, and the manifest check that guards resumes.

``results/<run>/`` holds::

    manifest.json     RunManifest: config + provenance, written once when the run starts
    records.jsonl     EpisodeRecord per line, append-only; the last line of a key wins
    responses.jsonl   CachedResponse per line: raw model answers by (episode key, prompt hash)
    summary.md/.csv   paper-layout summary tables (rewritten at the end of a run / rescore)
    .lock             held by the one process writing the folder
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from filelock import FileLock, Timeout
from pydantic import ValidationError

from vlm_bench.errors import ConfigError, DataFileError, VlmBenchError, first_problem
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.run import RunConfig, RunManifest, config_differences


class RunLockedError(VlmBenchError):
    """Another process is writing the run folder."""


class ConfigMismatchError(VlmBenchError):
    """The run folder holds a run with another configuration."""


class NotARunError(VlmBenchError):
    """The folder has no run manifest."""


@dataclass(frozen=True)
class RunPaths:
    """The files of one run folder."""

    root: Path

    @property
    def run_id(self) -> str:
        """The run id: the folder's name."""
        return self.root.name

    @property
    def manifest(self) -> Path:
        """``manifest.json``."""
        return self.root / "manifest.json"

    @property
    def records(self) -> Path:
        """``records.jsonl``."""
        return self.root / "records.jsonl"

    @property
    def responses(self) -> Path:
        """``responses.jsonl``."""
        return self.root / "responses.jsonl"

    @property
    def lock(self) -> Path:
        """``.lock``."""
        return self.root / ".lock"

    @property
    def summary_md(self) -> Path:
        """``summary.md``."""
        return self.root / "summary.md"

    @property
    def summary_csv(self) -> Path:
        """``summary.csv``."""
        return self.root / "summary.csv"


def make_run_folder(root: Path) -> None:
    """Create ``root`` (and its parents) unless it is a folder already.

    Raises:
        NotARunError: ``root`` is a file.
        ConfigError: A folder above it is a file, or it cannot be created (names the path).
    """
    if root.is_dir():
        return
    if root.exists():
        raise NotARunError(f"{root} is a file, not a run folder; choose a new or empty folder")
    blocking = next((p for p in root.parents if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        raise ConfigError(f"cannot create run folder {root}: {blocking} is a file")
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigError(f"cannot create run folder {root}: {exc.strerror}") from None


def acquire_lock(paths: RunPaths) -> FileLock:
    """Take the folder's writer lock without waiting.

    The lock is an OS file lock (``flock``): a killed process releases it automatically.

    Raises:
        RunLockedError: Another process (or another open store in this one) holds it.
        NotARunError, ConfigError: The folder cannot be created (see :func:`make_run_folder`).
    """
    make_run_folder(paths.root)
    lock = FileLock(str(paths.lock), timeout=0)
    try:
        lock.acquire()
    except Timeout:
        raise RunLockedError(
            f"{paths.root} is being written by another vlm-bench process "
            f"(lock {paths.lock}); wait for it to finish or choose another --run-name/--out"
        ) from None
    return lock


def read_manifest(paths: RunPaths) -> RunManifest:
    """Load ``manifest.json``.

    Raises:
        NotARunError: The folder has no manifest.
        DataFileError: The manifest is not valid JSON or misses a field (names the field).
    """
    if not paths.manifest.exists():
        raise NotARunError(f"{paths.root} is not a vlm-bench run folder (no manifest.json)")
    try:
        data = json.loads(paths.manifest.read_text(encoding="utf-8"))
        return RunManifest.model_validate(data)
    except UnicodeDecodeError:
        raise DataFileError(str(paths.manifest), "not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise DataFileError(str(paths.manifest), f"invalid JSON ({exc.msg})") from None
    except ValidationError as exc:
        where, why, _ = first_problem(exc)
        raise DataFileError(str(paths.manifest), f"{where or '(root)'}: {why}") from None


def write_manifest(paths: RunPaths, manifest: RunManifest) -> None:
    """Write ``manifest.json`` atomically."""
    write_text_atomic(paths.manifest, manifest.model_dump_json(indent=2) + "\n")


def check_compatible(
    paths: RunPaths, stored: RunManifest, config: RunConfig, new: RunManifest
) -> None:
    """Refuse to resume a run whose config or shipped data differ from the stored ones (the
    operational backend arguments ``new`` names may differ).

    Raises:
        ConfigMismatchError: One line naming every differing field.
    """
    fields = config_differences(stored.config, config, new.operational_args)
    if stored.config.benchmark_version != config.benchmark_version:
        raise ConfigMismatchError(
            f"{paths.root} holds a run of benchmark version {stored.config.benchmark_version}; "
            f"this release evaluates version {config.benchmark_version}, so it cannot resume "
            "that run: start a new one with another --out/--run-name (or resume it with the "
            "release that made it)"
        )
    data = [
        n
        for n in ("prompts", "skills", "ground_truth")
        if getattr(stored.data, n) != getattr(new.data, n)
    ]
    if data and not fields:
        rescore = (
            f", or score its saved answers against these files: vlm-bench rescore {paths.root}"
            if stored.config.loop == "open"
            else ""
        )
        raise ConfigMismatchError(
            f"{paths.root} holds a run made with other {'/, '.join(data)}/ files than this "
            "installation's, so re-running cannot resume it: start a new run with another "
            f"--out/--run-name{rescore}"
        )
    fields += [f"{name}/ files" for name in data]
    if fields:
        raise ConfigMismatchError(
            f"{paths.root} holds a run with a different configuration "
            f"(differs: {', '.join(fields)}); re-run with the same options to resume, "
            "or choose another --run-name/--out"
        )
