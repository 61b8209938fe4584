"""Where the shipped data folders live, for both a source checkout and an installed wheel."""

from __future__ import annotations

import os
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent
_DATA_FOLDERS = ("prompts", "ground_truth", "skills", "models")


def data_root() -> Path:
    """Return the folder that holds ``prompts/``, ``ground_truth/`` and ``skills/``.

    ``VLM_BENCH_DATA_DIR`` overrides it. A wheel carries the folders under ``vlm_bench/_data``;
    a source checkout has them at the repository root, next to the package.
    """
    override = os.environ.get("VLM_BENCH_DATA_DIR")
    if override:
        return Path(override)
    packaged = _PACKAGE_DIR / "_data"
    if (packaged / "ground_truth").is_dir():
        return packaged
    return _PACKAGE_DIR.parent


def prompts_dir() -> Path:
    """Jinja2 prompt templates."""
    return data_root() / "prompts"


def ground_truth_dir() -> Path:
    """Task specs, world catalogue and materialised episodes."""
    return data_root() / "ground_truth"


def skills_dir() -> Path:
    """Skill library data files."""
    return data_root() / "skills"


def models_dir() -> Path:
    """Model cards (recipes of the paper's VLMs)."""
    return data_root() / "models"


def results_dir() -> Path:
    """Default folder for run outputs (``VLM_BENCH_RESULTS_DIR`` overrides)."""
    override = os.environ.get("VLM_BENCH_RESULTS_DIR")
    return Path(override) if override else Path.cwd() / "results"
