"""Rows streamed into parquet shards that ``datasets.load_dataset(folder)`` reads with their
features (the ``huggingface`` schema metadata ``datasets`` writes itself): at most
:data:`ROWS_PER_SHARD` rows held in memory, the same bytes for the same rows."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from vlm_bench.errors import MissingExtraError

ROWS_PER_SHARD = 256
"""Rows per parquet file (and most rows held in memory)."""

SHARD_GLOB = "data/train-*.parquet"
"""Where the shards lie in the folder (the card's ``data_files``)."""


def require_datasets() -> Any:
    """The ``datasets`` module.

    Raises:
        MissingExtraError: ``datasets`` (or ``pyarrow``) is not installed; names the extra.
    """
    try:
        import datasets
        import pyarrow  # noqa: F401
    except ImportError:
        raise MissingExtraError("datasets", "train") from None
    return datasets


class ShardWriter:
    """Writes rows (plain dicts matching ``features``) into ``folder/data/train-NNNNN.parquet``.

    Args:
        folder: The dataset folder (created).
        features: A ``datasets.Features``.
        rows_per_shard: Rows per file.
    """

    def __init__(self, folder: Path, features: Any, rows_per_shard: int = ROWS_PER_SHARD) -> None:
        self.folder = folder
        self.features = features
        self.rows_per_shard = rows_per_shard
        self.shards: list[Path] = []
        self.rows = 0
        self._pending: list[dict[str, Any]] = []

    def write(self, rows: Sequence[Mapping[str, Any]]) -> None:
        """Queue ``rows``; full shards are written at once."""
        for row in rows:
            self._pending.append(self.features.encode_example(dict(row)))
            if len(self._pending) >= self.rows_per_shard:
                self._flush()

    def close(self) -> list[Path]:
        """Write the last shard; the shard paths in order."""
        if self._pending or not self.shards:
            self._flush()
        return self.shards

    def _flush(self) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        path = self.folder / "data" / f"train-{len(self.shards):05d}.parquet"
        path.parent.mkdir(parents=True, exist_ok=True)
        schema = self.features.arrow_schema
        table = pa.Table.from_pylist(self._pending, schema=schema)
        pq.write_table(table, path, compression="zstd")
        self.shards.append(path)
        self.rows += len(self._pending)
        self._pending = []
