"""Package faces (docs/decisions.md, "Code layout and tests"): a package's ``__init__``
re-exports what is imported through it (by another package, the tests, the benchmarks or the
docs' examples), nothing more; everything else is imported from the module that defines it."""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = sorted(p.parent.name for p in (ROOT / "vlm_bench").glob("*/__init__.py"))


def _sources() -> Iterator[tuple[str | None, str]]:
    """(package the code belongs to, or None outside vlm_bench's packages; Python source)."""
    for folder in ("vlm_bench", "tests", "benchmarks"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT).parts
            yield (parts[1] if folder == "vlm_bench" and len(parts) > 2 else None), path.read_text()
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for block in re.findall(r"```python\n(.*?)```", doc.read_text(), re.S):
            yield None, block


@cache
def imported_through_faces() -> dict[str, set[str]]:
    """Names imported as ``from vlm_bench.<package> import name`` from outside the package."""
    out: dict[str, set[str]] = {p: set() for p in PACKAGES}
    for owner, source in _sources():
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                parts = node.module.split(".")
                inside = len(parts) == 2 and parts[0] == "vlm_bench" and parts[1] in out
                if inside and parts[1] != owner:
                    out[parts[1]].update(alias.name for alias in node.names)
    return out


def face(package: str) -> tuple[set[str], set[str]]:
    """(names the package's ``__init__`` imports, its ``__all__``)."""
    tree = ast.parse((ROOT / "vlm_bench" / package / "__init__.py").read_text())
    imported = {
        a.asname or a.name for n in tree.body if isinstance(n, ast.ImportFrom) for a in n.names
    }
    listed: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            listed = {ast.literal_eval(e) for e in node.value.elts}  # type: ignore[attr-defined]
    return imported, listed


@pytest.mark.parametrize("package", PACKAGES)
def test_a_face_lists_what_is_imported_through_it(package: str) -> None:
    imported, listed = face(package)
    assert imported == listed, "re-exported but not in __all__ (or the reverse)"
    unused = listed - imported_through_faces()[package]
    assert not unused, f"in vlm_bench.{package}.__all__ but never imported through it: {unused}"
