"""``vlm-bench export dataset``: the benchmark as a Hugging Face dataset folder (Parquet shards
under ``data/`` and a ``README.md`` card) that ``datasets.load_dataset(folder)`` loads as is.

Written into a staging folder beside the target and moved into place at the end, so an
interrupted export leaves no half-written dataset.
"""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from vlm_bench.errors import ConfigError
from vlm_bench.export.card import SPLIT, card_text
from vlm_bench.export.features import dataset_features, require_dataset_extra, row_record
from vlm_bench.export.options import ExportOptions
from vlm_bench.export.parquet_writer import DEFAULT_SHARD_ROWS, shard_names, write_shards
from vlm_bench.export.row_model import DatasetRow
from vlm_bench.export.rows import episode_refs, iter_rows

DATA_FOLDER = "data"
"""The shards' folder inside the dataset folder."""


@dataclass(frozen=True)
class DatasetExport:
    """What an export wrote."""

    folder: Path
    """The dataset folder."""
    rows: int
    """Rows written (episodes)."""
    shards: tuple[Path, ...]
    """The Parquet files, in order."""
    bytes: int
    """Size of the shards and the card on disk."""


def check_target(out: Path, force: bool) -> None:
    """Refuse a target that is a file, or a non-empty folder without ``force``.

    Raises:
        ConfigError: One line naming the folder and what to do.
    """
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out} is a file, not a folder")
    blocking = next((p for p in out.parents if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        raise ConfigError(f"{out}: {blocking} is a file, not a folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise ConfigError(f"{out} is not empty; pass --force to replace the dataset in it")


def export_dataset(
    out: Path,
    options: ExportOptions,
    *,
    force: bool = False,
    snapshot_cache: Path | None = None,
    shard_rows: int = DEFAULT_SHARD_ROWS,
    progress: bool = True,
) -> DatasetExport:
    """Write the episodes ``options`` select as a dataset folder at ``out``.

    Args:
        out: The dataset folder (created; must be empty unless ``force``).
        options: Episode selection and prompt options.
        force: Replace the card and ``data/`` of a non-empty ``out`` (other files stay).
        snapshot_cache: The shared PNG cache folder runs use, or None to render.
        shard_rows: Rows per Parquet file.
        progress: Show a progress bar on stderr.

    Raises:
        MissingExtraError: ``datasets`` or ``pyarrow`` missing (the ``dataset`` extra).
        ConfigError / UnknownNameError: A bad target or option, before anything is written.
    """
    from vlm_bench.runner.progress import progress_bar
    from vlm_bench.storage.provenance import package_versions

    require_dataset_extra()
    if shard_rows < 1:
        raise ConfigError(f"--shard-rows must be at least 1, got {shard_rows}")
    check_target(out, force)
    refs = episode_refs(options)  # validates every option before anything is written
    features = dataset_features(options.views)
    names = shard_names(SPLIT, len(refs), shard_rows)
    staging = out.parent / f".{out.name}.partial"
    if staging.exists():
        shutil.rmtree(staging)  # a previous export that was interrupted
    first: list[DatasetRow] = []

    def records() -> Iterator[dict[str, object]]:
        for row in iter_rows(options, snapshot_cache):
            if not first:
                first.append(row)
            yield row_record(row)

    try:
        with progress_bar(len(refs), "export", enabled=progress) as advance:
            writer = write_shards(
                records(), staging / DATA_FOLDER, features, names, shard_rows, advance
            )
        example = first[0] if first else None
        version = package_versions(("vlm-bench",)).get("vlm-bench", "unknown")
        card = card_text(options, features, writer.rows, writer.arrow_bytes, version, example)
        (staging / "README.md").write_text(card, encoding="utf-8")
        install_staged(staging, out)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    shards = tuple(out / DATA_FOLDER / name for name in names)
    size = sum(p.stat().st_size for p in shards) + (out / "README.md").stat().st_size
    return DatasetExport(out, writer.rows, shards, size)


def install_staged(staging: Path, out: Path) -> None:
    """Move a dataset staged in ``staging`` (its ``README.md`` card and its ``data/`` shards)
    into ``out``, replacing an earlier export's, and remove ``staging``; what else ``out``
    holds stays."""
    out.mkdir(parents=True, exist_ok=True)
    old_data = out / DATA_FOLDER
    if old_data.is_dir():
        shutil.rmtree(old_data)
    elif old_data.exists():
        old_data.unlink()
    (staging / DATA_FOLDER).rename(old_data)
    (staging / "README.md").replace(out / "README.md")
    staging.rmdir()
