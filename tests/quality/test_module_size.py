"""No module of the package is over 350 lines (docs/design.md: one concept per file; a module
that outgrows the bound is split where a concept separates)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAX_LINES = 350


def oversized(root: Path, limit: int) -> dict[str, int]:
    """The Python files under ``root`` longer than ``limit`` lines, with their lengths."""
    sizes = {
        str(path.relative_to(root.parent)): len(path.read_text(encoding="utf-8").splitlines())
        for path in sorted(root.rglob("*.py"))
    }
    return {name: n for name, n in sizes.items() if n > limit}


def test_the_size_check_finds_a_long_module(tmp_path: Path) -> None:
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "short.py").write_text("x = 1\n" * 3)
    (package / "sub" / "long.py").write_text("x = 1\n" * 4)
    assert oversized(package, 3) == {"pkg/sub/long.py": 4}


def test_no_module_is_over_350_lines() -> None:
    assert oversized(ROOT / "vlm_bench", MAX_LINES) == {}
