"""The SFT export as a dataset folder (docs/training.md#sft-export-schema): its columns, and the
streamed write through the dataset export's own Parquet writer and staging
(:mod:`vlm_bench.export`): shards named as the Hub names them, the same bytes for the same rows,
and nothing half-written where an export stops."""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vlm_bench.export.dataset_export import DATA_FOLDER, check_target, install_staged
from vlm_bench.export.features import require_dataset_extra
from vlm_bench.export.parquet_writer import DEFAULT_SHARD_ROWS, ShardWriter, shard_names
from vlm_bench.runner.progress import progress_bar
from vlm_bench.training.sft_card import SPLIT, sft_card
from vlm_bench.training.sft_export import SftCounts, row_bound, scene_count, sft_examples
from vlm_bench.training.sft_rows import SftExample
from vlm_bench.types.run import RunConfig

if TYPE_CHECKING:
    import datasets


def sft_features() -> datasets.Features:
    """The columns: one per :class:`~vlm_bench.training.sft_rows.SftExample` field (lists
    spelled ``[feature]``, as the dataset export spells them)."""
    from datasets import Features, Image, Value

    part = {"type": Value("string"), "text": Value("string")}
    return Features(
        {
            "key": Value("string"),
            "task_id": Value("string"),
            "suite": Value("string"),
            "seed": Value("int64"),
            "instruction": Value("string"),
            "round": Value("int32"),
            "kind": Value("string"),
            "messages": [{"role": Value("string"), "content": [part]}],
            "images": [Image()],
            "target": Value("string"),
            "prompt_hash": Value("string"),
        }
    )


def sft_record(example: SftExample) -> dict[str, Any]:
    """A row as a record of :func:`sft_features` (images as PNG bytes)."""
    record = example.model_dump(exclude={"images", "messages"})
    record["messages"] = list(example.messages)
    record["images"] = [{"bytes": png, "path": None} for png in example.images]
    return record


@dataclass(frozen=True)
class SftExport:
    """What :func:`export_sft` wrote."""

    folder: Path
    rows: int
    counts: SftCounts
    shards: tuple[Path, ...]


def export_sft(
    config: RunConfig,
    out: Path,
    *,
    force: bool = False,
    allow_test_seeds: bool = False,
    shard_rows: int = DEFAULT_SHARD_ROWS,
    progress: bool = False,
) -> SftExport:
    """Write the SFT dataset of ``config``'s selection and prompt options into ``out``.

    Args:
        config: Selection (tasks or suite, seeds, instructions), prompt options, and
            ``perturb`` (with ``max_rounds``, ``history``) for replan rows.
        out: The dataset folder (empty, or ``force``: its card and ``data/`` are replaced).
        force: Write into a non-empty folder.
        allow_test_seeds: Accept seeds 0-9 (the card says so).
        shard_rows: Rows per Parquet file.
        progress: A progress bar on stderr (one step per task x seed).

    Raises:
        MissingExtraError: ``datasets`` or ``pyarrow`` is missing (the ``dataset`` extra).
        ConfigError: Test seeds without ``allow_test_seeds``, a non-empty ``out``: before
            anything is written.
    """
    require_dataset_extra()
    check_target(out, force)
    counts = SftCounts()
    examples = sft_examples(config, counts, allow_test_seeds=allow_test_seeds)  # checks now
    features = sft_features()
    bound = shard_names(SPLIT, row_bound(config), shard_rows)
    staging = out.parent / f".{out.name}.partial"
    if staging.exists():
        shutil.rmtree(staging)  # an export that was interrupted
    try:
        writer = ShardWriter(staging / DATA_FOLDER, features, bound, shard_rows)
        with progress_bar(scene_count(config), "sft export", enabled=progress) as advance:
            for done, rows in examples:
                for row in rows:
                    writer.add(sft_record(row))
                advance(done)
        written = writer.close()
        names = shard_names(SPLIT, writer.rows, shard_rows)  # the count is known now
        for path, name in zip(written, names, strict=True):
            path.rename(path.with_name(name))
        card = sft_card(config, counts, features, writer.arrow_bytes)
        (staging / "README.md").write_text(card, encoding="utf-8")
        install_staged(staging, out)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    shards = tuple(out / DATA_FOLDER / name for name in names)
    return SftExport(out, writer.rows, counts, shards)
