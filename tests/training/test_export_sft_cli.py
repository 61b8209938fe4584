"""``vlm-bench export sft``: a dataset ``datasets.load_dataset`` reads with its features, the same
bytes twice, and one line with nothing written for bad input (test seeds, a non-empty folder,
``datasets`` missing)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from tests.conftest import Cli

datasets = pytest.importorskip("datasets")

TASK = "standard_pick_place"
SMALL = ("--task", TASK, "--resolution", "32", "--k-shot", "0", "--no-progress")


def _files(folder: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def test_export_loads_with_its_features_and_is_deterministic(cli: Cli, tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    cli.invoke("export", "sft", str(a), "--seeds", "12", *SMALL)
    cli.invoke("export", "sft", str(b), "--seeds", "12", *SMALL)
    assert _files(a) == _files(b) and "README.md" in _files(a)
    rows = datasets.load_dataset(str(a), split="train", cache_dir=str(tmp_path / "cache"))
    assert rows.features["images"].feature == datasets.Image()
    assert [r["key"] for r in rows] == [f"{TASK}/12/explicit/0", f"{TASK}/12/implicit/0"]
    assert all(r["kind"] == "plan" and r["round"] == 0 and len(r["images"]) == 4 for r in rows)
    card = (a / "README.md").read_text()
    header = card.split("---\n")[1]
    assert "configs:" in header and "num_examples: 2" in header and "seeds: train" in header
    assert "Contains test seeds" not in card
    assert sorted(p.name for p in (a / "data").iterdir()) == ["train-00000-of-00001.parquet"]


def test_a_test_seed_is_refused_unless_allowed_and_then_the_card_says_so(
    cli: Cli, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    done = cli.run("export", "sft", str(out), "--seeds", "9-10", *SMALL)
    assert done.returncode == 2
    (line,) = done.stderr.strip().splitlines()
    assert "test seeds asked for (9)" in line and "--allow-test-seeds" in line
    assert not out.exists()
    cli.invoke(
        "export",
        "sft",
        str(out),
        "--seeds",
        "0",
        "--instruction",
        "explicit",
        "--allow-test-seeds",
        *SMALL,
    )
    assert "**Contains test seeds 0**" in (out / "README.md").read_text()


def test_a_non_empty_folder_is_refused_without_force(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    done = cli.run("export", "sft", str(out), "--seeds", "12", *SMALL)
    assert done.returncode == 2
    (line,) = done.stderr.strip().splitlines()
    assert "is not empty" in line and "--force" in line
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no staging folder left
    assert _files(out) == {"notes.txt": b"mine"}


def test_missing_datasets_names_the_extra(
    cli: Cli, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "datasets", None)  # import datasets raises ImportError
    done = cli.result("export", "sft", str(tmp_path / "out"), "--seeds", "12", *SMALL)
    assert done.exit_code != 0
    assert "datasets is not installed" in str(done.exception)
    assert "pip install 'vlm-bench[dataset]'" in str(done.exception)
    assert not (tmp_path / "out").exists()
