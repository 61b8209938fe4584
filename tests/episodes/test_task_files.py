"""Corrupted or wrong task files give one-line errors naming the file and the field."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from vlm_bench.catalog import tasks as task_catalog
from vlm_bench.catalog import world_catalog
from vlm_bench.errors import DataFileError
from vlm_bench.resources import ground_truth_dir, skills_dir


@pytest.fixture
def data_copy(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    shutil.copytree(ground_truth_dir(), tmp_path / "ground_truth")
    shutil.copytree(skills_dir(), tmp_path / "skills")
    monkeypatch.setenv("VLM_BENCH_DATA_DIR", str(tmp_path))
    task_catalog.all_tasks.cache_clear()
    world_catalog.world.cache_clear()
    yield tmp_path
    task_catalog.all_tasks.cache_clear()
    world_catalog.world.cache_clear()


def _first_task_file(root: Path) -> Path:
    return sorted((root / "ground_truth" / "tasks" / "base_manipulation").glob("*.json"))[0]


def _edit_first_task_file(root: Path, edit: Callable[[dict[str, Any]], object]) -> Path:
    """The first task file, rewritten with ``edit`` applied to its JSON."""
    path = _first_task_file(root)
    data = json.loads(path.read_text())
    edit(data)
    path.write_text(json.dumps(data))
    return path


def test_missing_field(data_copy: Path) -> None:
    path = _edit_first_task_file(data_copy, lambda data: data.pop("instructions"))
    with pytest.raises(DataFileError) as err:
        task_catalog.all_tasks()
    msg = str(err.value)
    assert path.name in msg and "instructions" in msg and "\n" not in msg


def test_unknown_object_kind(data_copy: Path) -> None:
    _edit_first_task_file(data_copy, lambda data: data["objects"][1].update(kind="spaceship"))
    with pytest.raises(DataFileError, match=r"objects\[1\]\.kind: unknown object kind 'spaceship'"):
        task_catalog.all_tasks()


def test_invalid_json(data_copy: Path) -> None:
    path = _first_task_file(data_copy)
    path.write_text("{not json")
    with pytest.raises(DataFileError, match="invalid JSON at line 1"):
        task_catalog.all_tasks()


def test_dangling_reference(data_copy: Path) -> None:
    _edit_first_task_file(data_copy, lambda data: data["arm_steps"][0].update(object="ghost"))
    with pytest.raises(DataFileError, match=r"arm_steps\[0\]\.object: unknown object 'ghost'"):
        task_catalog.all_tasks()
