"""Provenance for run manifests: data-folder digests, package versions, git revision.

Nothing here imports heavy packages: versions come from ``importlib.metadata``.
"""

from __future__ import annotations

import hashlib
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from vlm_bench.resources import data_root, ground_truth_dir, prompts_dir, skills_dir
from vlm_bench.types.run import DataHashes

PACKAGES = ("vlm-bench", "mujoco", "pydantic", "numpy", "transformers", "torch", "vllm", "openai")
"""Distributions whose versions the manifest records (those installed)."""


def folder_digest(folder: Path) -> str:
    """sha256 over the relative paths and bytes of every file under ``folder`` (sorted).

    Hidden files and ``__pycache__`` folders are skipped. A missing folder hashes as
    empty.
    """
    digest = hashlib.sha256()
    if folder.is_dir():
        for path in sorted(folder.rglob("*")):
            rel = path.relative_to(folder)
            if not path.is_file() or any(
                p.startswith(".") or p == "__pycache__" for p in rel.parts
            ):
                continue
            digest.update(rel.as_posix().encode() + b"\0")
            digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def data_hashes() -> DataHashes:
    """Digests of ``prompts/``, ``skills/`` and ``ground_truth/``."""
    return DataHashes(
        prompts=folder_digest(prompts_dir()),
        skills=folder_digest(skills_dir()),
        ground_truth=folder_digest(ground_truth_dir()),
    )


def package_versions(names: tuple[str, ...] = PACKAGES) -> dict[str, str]:
    """Installed versions of ``names`` (missing distributions are left out)."""
    out: dict[str, str] = {}
    for name in names:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return out


def git_revision(folder: Path | None = None) -> str | None:
    """The commit of the checkout holding the data (``<sha>+dirty`` with local changes).

    Returns None outside a git checkout or without git.
    """
    where = folder or data_root()
    if not (where / ".git").exists():
        return None
    try:
        head = _git(where, "rev-parse", "HEAD")
        dirty = _git(where, "status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return f"{head}+dirty" if dirty else head


def _git(folder: Path, *args: str) -> str:
    """The stripped output of ``git args`` in ``folder`` (raises on failure or after 10 s)."""
    done = subprocess.run(
        ["git", *args], cwd=folder, capture_output=True, text=True, timeout=10, check=True
    )
    return done.stdout.strip()


def machine() -> str:
    """OS and architecture, e.g. ``Linux-6.8-x86_64``."""
    return f"{platform.system()}-{platform.release()}-{platform.machine()}"
