"""Every file docs/design.md names exists, so its "How to add" lists and its tour of the runner
stay true as files move."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "design.md"
SUFFIXES = (".py", ".json", ".j2", ".md", ".toml")
PLACES = ("", "vlm_bench/", "docs/")
"""Where a named path may start: the repository, the package, the docs."""


def named_paths(text: str) -> set[str]:
    """The file paths in backticks with a folder part (``runner/pipeline.py``), placeholders
    such as ``skills/<name>.json`` and dotted module names left out."""
    spans = re.findall(r"`([^`\s]+)`", text)
    return {
        s.split(":")[0]
        for s in spans
        if "/" in s and "<" not in s and s.split(":")[0].endswith(SUFFIXES)
    }


def missing(paths: set[str], root: Path) -> list[str]:
    """The paths found under none of :data:`PLACES` of ``root``."""
    return sorted(p for p in paths if not any((root / place / p).exists() for place in PLACES))


def test_a_moved_file_is_found_missing(tmp_path: Path) -> None:
    (tmp_path / "vlm_bench" / "runner").mkdir(parents=True)
    (tmp_path / "vlm_bench" / "runner" / "pipeline.py").write_text("")
    text = "see `runner/pipeline.py`, `runner/gone.py` and `skills/<name>.json`"
    assert missing(named_paths(text), tmp_path) == ["runner/gone.py"]


def test_every_file_design_md_names_exists() -> None:
    paths = named_paths(DOC.read_text(encoding="utf-8"))
    assert len(paths) > 20  # the doc names files; a broken pattern would find none
    assert missing(paths, ROOT) == []
