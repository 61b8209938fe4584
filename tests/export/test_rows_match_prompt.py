"""Every exported row is what ``vlm-bench prompt`` prints for its episode, and its images are
the PNGs that command writes (the request a run sends: tests/cli/test_cli_prompt.py)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import datasets
import pytest

from vlm_bench.catalog.tasks import tasks_in
from vlm_bench.export.dataset_export import DatasetExport
from vlm_bench.export.row_model import image_column

if TYPE_CHECKING:
    from tests.conftest import Cli

SAMPLE_TASKS = tuple(t.id for t in tasks_in(None))[::4]
"""Every fourth task (15, from all four suites)."""


def _prompt_of(cli: Cli, row: dict[str, Any], out: Path, *options: str) -> str:
    task, seed, variant = row["key"].split("/")
    return cli.invoke(
        "prompt", task, "--seed", seed, "--instruction", variant, "--out", str(out), *options
    )


def _check_rows(
    cli: Cli, folder: Path, tmp_path: Path, cache: Path, monkeypatch: pytest.MonkeyPatch
) -> int:
    """Compare every row with ``vlm-bench prompt`` (same snapshot cache); returns the rows."""
    monkeypatch.setenv("VLM_BENCH_SNAPSHOT_CACHE", str(cache))
    rows = datasets.load_dataset(str(folder), split="test")
    for column, feature in rows.features.items():
        if isinstance(feature, datasets.Image):  # the stored bytes, not decoded pixels
            rows = rows.cast_column(column, datasets.Image(decode=False))
    for i, row in enumerate(rows):
        out = tmp_path / str(i)
        printed = _prompt_of(cli, row, out)
        assert printed.startswith(
            f"### system\n{row['system'].rstrip()}\n\n### user\n{row['user'].rstrip()}\n"
        ), row["key"]
        assert f"prompt hash {row['prompt_hash']}" in printed
        assert sorted(p.stem for p in out.iterdir()) == sorted(row["views"])
        for view in row["views"]:
            png = (out / f"{view}.png").read_bytes()
            assert row[image_column(view)]["bytes"] == png, (row["key"], view)
    return len(rows)


def test_a_sixty_row_sample_is_the_prompt_a_run_sends(
    cli: Cli,
    exporter: Callable[..., DatasetExport],
    snapshot_cache: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    made = exporter("sample", tasks=SAMPLE_TASKS, seeds=(0, 7))
    assert made.rows == 60
    assert _check_rows(cli, made.folder, tmp_path, snapshot_cache, monkeypatch) == 60


@pytest.mark.slow
def test_the_default_export_is_the_prompt_a_run_sends(
    cli: Cli, tmp_path: Path, snapshot_cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from vlm_bench.export.dataset_export import export_dataset
    from vlm_bench.export.options import ExportOptions

    made = export_dataset(
        tmp_path / "ds", ExportOptions(), snapshot_cache=snapshot_cache, progress=False
    )
    assert made.rows == 1200
    assert _check_rows(cli, made.folder, tmp_path / "p", snapshot_cache, monkeypatch) == 1200
