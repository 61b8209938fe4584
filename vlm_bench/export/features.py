"""The dataset's columns as ``datasets`` features, and a row as a record of them."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from vlm_bench.errors import MissingExtraError
from vlm_bench.export.row_model import DatasetRow, image_column

if TYPE_CHECKING:
    import datasets


def require_dataset_extra() -> None:
    """Refuse to go on without ``datasets`` and ``pyarrow`` (the ``dataset`` extra).

    Raises:
        MissingExtraError: Names the extra to install.
    """
    import importlib

    for package in ("pyarrow", "datasets"):
        try:
            importlib.import_module(package)
        except ImportError:
            raise MissingExtraError(package, "dataset") from None


def dataset_features(views: Sequence[str]) -> datasets.Features:
    """The columns of a dataset showing ``views``: one ``datasets.Image`` column per view.

    Lists are written ``[feature]`` (an Arrow list, a list of structs for ``gt_steps``), the
    one spelling every ``datasets`` release reads alike.
    """
    from datasets import Features, Image, Value

    step = {
        "subtask": Value("int32"),
        "tasktype": Value("string"),
        "direction": Value("string"),
        "distance": Value("float64"),
        "object": Value("string"),
        "skill": Value("string"),
        "target": Value("string"),
    }
    columns: dict[str, Any] = {
        "key": Value("string"),
        "benchmark_version": Value("int32"),
        "task_id": Value("string"),
        "suite": Value("string"),
        "seed": Value("int64"),
        "instruction": Value("string"),
        "instruction_text": Value("string"),
        "system": Value("string"),
        "user": Value("string"),
        "views": [Value("string")],
    }
    for view in views:
        columns[image_column(view)] = Image()
    columns.update(
        {
            "objects": [Value("string")],
            "gt_plan": Value("string"),
            "gt_steps": [step],
            "prompt_hash": Value("string"),
            "example_ids": [Value("string")],
        }
    )
    return Features(columns)


def row_record(row: DatasetRow) -> dict[str, Any]:
    """A row as a record of :func:`dataset_features`' columns (images as PNG bytes)."""
    record: dict[str, Any] = {
        "key": row.key,
        "benchmark_version": row.benchmark_version,
        "task_id": row.task_id,
        "suite": row.suite,
        "seed": row.seed,
        "instruction": row.instruction,
        "instruction_text": row.instruction_text,
        "system": row.system,
        "user": row.user,
        "views": list(row.views),
    }
    for view in row.views:
        record[image_column(view)] = {"bytes": row.images[view], "path": None}
    record.update(
        {
            "objects": list(row.objects),
            "gt_plan": row.gt_plan,
            "gt_steps": [step.model_dump() for step in row.gt_steps],
            "prompt_hash": row.prompt_hash,
            "example_ids": list(row.example_ids),
        }
    )
    return record
