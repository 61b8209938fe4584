"""Dataset rows as inspect samples: the system message and the user turn a run sends, each
image where the run puts it (as a PNG file, so a 1,200-episode task stays small in memory).

Rows come from the export's own row builder (:func:`vlm_bench.export.rows.iter_rows`), or from
an exported dataset folder; the sample's metadata is what :func:`vlm_bench.score_answer` needs.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vlm_bench.errors import DataFileError
from vlm_bench.export.row_model import DatasetRow, image_column, user_parts
from vlm_bench.inspect_eval.options import TaskOptions

if TYPE_CHECKING:
    from inspect_ai.dataset import Sample

SCORED_FIELDS = ("key", "benchmark_version", "task_id", "suite", "seed", "instruction")
"""Row fields kept in a sample's metadata (with ``objects`` and ``gt_plan``)."""


def png_file(png: bytes, folder: Path) -> Path:
    """``png`` as a file named by its sha256 under ``folder`` (written once)."""
    digest = hashlib.sha256(png).hexdigest()
    path = folder / digest[:2] / f"{digest}.png"
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_suffix(f".{digest[:8]}.part")
        partial.write_bytes(png)
        partial.replace(path)
    return path


def sample_of(row: DatasetRow, images: Path) -> Sample:
    """One inspect sample: system + user messages, the GT plan as target, the row's scoring
    fields as metadata (``suite`` groups the metrics)."""
    from inspect_ai.dataset import Sample
    from inspect_ai.model import (
        ChatMessageSystem,
        ChatMessageUser,
        Content,
        ContentImage,
        ContentText,
    )

    content: list[Content] = []
    for kind, value in user_parts(row.user):
        if kind == "text":
            content.append(ContentText(text=value))
        else:
            content.append(ContentImage(image=str(png_file(row.images[value], images))))
    metadata: dict[str, Any] = {name: getattr(row, name) for name in SCORED_FIELDS}
    metadata.update(objects=list(row.objects), gt_plan=row.gt_plan, views=list(row.views))
    return Sample(
        id=row.key,
        input=[ChatMessageSystem(content=row.system), ChatMessageUser(content=content)],
        target=row.gt_plan,
        metadata=metadata,
    )


def _selected(row: dict[str, Any], options: TaskOptions) -> bool:
    chosen = options.episodes
    if chosen.tasks and row["task_id"] not in chosen.tasks:
        return False
    if chosen.suite is not None and row["suite"] != chosen.suite.value:
        return False
    return row["seed"] in chosen.seeds and row["instruction"] in chosen.instructions


def folder_rows(folder: Path, options: TaskOptions) -> Iterator[DatasetRow]:
    """The rows of an exported dataset folder that the options select, PNG bytes as written.

    Raises:
        MissingExtraError: ``datasets`` missing (the ``dataset`` extra).
        DataFileError: A folder ``datasets`` cannot load as this benchmark's export.
    """
    from vlm_bench.export.card import SPLIT
    from vlm_bench.export.features import require_dataset_extra

    require_dataset_extra()
    import datasets

    try:
        data = datasets.load_dataset(str(folder), split=SPLIT)
    except (ValueError, FileNotFoundError, datasets.exceptions.DatasetGenerationError) as exc:
        raise DataFileError(str(folder), f"not a vlm-bench dataset: {exc}") from None
    for column, feature in data.features.items():
        if isinstance(feature, datasets.Image):
            data = data.cast_column(column, datasets.Image(decode=False))
    for row in data:
        if not _selected(row, options):
            continue
        views = tuple(row["views"])
        images = {view: row[image_column(view)]["bytes"] for view in views}
        fields = {k: v for k, v in row.items() if not k.startswith("image_")}
        yield DatasetRow.model_validate({**fields, "views": views, "images": images})


def task_samples(options: TaskOptions, images: Path, snapshot_cache: Path | None) -> list[Sample]:
    """The task's samples in benchmark order (rows built in-process, or read from
    ``options.dataset``).

    Args:
        options: The task's options.
        images: Folder for the samples' PNG files.
        snapshot_cache: The PNG cache runs share (in-process rows), or None to render.
    """
    from vlm_bench.export.rows import iter_rows

    if options.dataset is not None:
        rows: Iterator[DatasetRow] = folder_rows(options.dataset, options)
    else:
        rows = iter_rows(options.episodes, snapshot_cache)
    return [sample_of(row, images) for row in rows]
