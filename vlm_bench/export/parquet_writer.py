"""Rows to Parquet shards, streamed: at most one row group of rows is held in memory.

Shards are named as the Hugging Face Hub names them (``<split>-00000-of-00003.parquet``), so a
folder of them loads with ``datasets.load_dataset`` and uploads as is. The bytes depend only on
the rows, the columns and the pyarrow version: no timestamps, no paths.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import datasets
    import pyarrow as pa
    import pyarrow.parquet as pq

DEFAULT_SHARD_ROWS = 100
"""Rows per Parquet file (about 33 MB at four 448-px views)."""

ROW_GROUP_ROWS = 10
"""Rows per Parquet row group: the rows held in memory at once (readers decode a group at a
time, as ``datasets``' own image writer does with groups of 100)."""


def shard_names(split: str, rows: int, shard_rows: int) -> list[str]:
    """The shard file names of ``rows`` rows, ``shard_rows`` to a file (at least one file)."""
    count = max(1, math.ceil(rows / shard_rows))
    return [f"{split}-{i:05d}-of-{count:05d}.parquet" for i in range(count)]


class ShardWriter:
    """Writes records of fixed columns to numbered Parquet shards in a folder.

    Args:
        folder: Where the shards go (created).
        features: The columns (``datasets.Features``: their Arrow schema carries the features
            as ``datasets`` reads them back).
        names: The shard file names, in order (:func:`shard_names`).
        shard_rows: Rows per shard.
    """

    def __init__(
        self, folder: Path, features: datasets.Features, names: Sequence[str], shard_rows: int
    ) -> None:
        self.folder = folder
        self.features = features
        self.schema: pa.Schema = _deterministic_schema(features)
        self.names = list(names)
        self.shard_rows = shard_rows
        self.rows = 0
        self.bytes = 0
        self.arrow_bytes = 0
        self._group: list[dict[str, Any]] = []
        self._writer: pq.ParquetWriter | None = None
        self._shard = -1
        folder.mkdir(parents=True, exist_ok=True)

    def add(self, record: dict[str, Any]) -> None:
        """Add one record (column → value, images as ``{"bytes": png, "path": None}``)."""
        if self.rows and self.rows % self.shard_rows == 0:
            self._flush()
            self._close_shard()
        self._group.append(self.features.encode_example(record))
        self.rows += 1
        if len(self._group) >= ROW_GROUP_ROWS:
            self._flush()

    def close(self) -> list[Path]:
        """Write what is left (an empty shard when no record came); returns the shard paths."""
        self._flush()
        if self._shard < 0:
            self._open_next()
        self._close_shard()
        return [self.folder / name for name in self.names[: self._shard + 1]]

    def _flush(self) -> None:
        if not self._group:
            return
        import pyarrow as pa

        if self._writer is None:
            self._open_next()
        assert self._writer is not None
        table = pa.Table.from_pylist(self._group, schema=self.schema)
        self.arrow_bytes += table.nbytes
        self._writer.write_table(table, row_group_size=len(self._group))
        self._group = []

    def _open_next(self) -> None:
        import pyarrow.parquet as pq

        self._shard += 1
        if self._shard >= len(self.names):
            raise ValueError(f"more rows than the {len(self.names)} shard(s) announced")
        path = self.folder / self.names[self._shard]
        self._writer = pq.ParquetWriter(path, self.schema, compression="zstd")

    def _close_shard(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self.bytes += (self.folder / self.names[self._shard]).stat().st_size
            self._writer = None


def _deterministic_schema(features: datasets.Features) -> pa.Schema:
    """The features' Arrow schema with its ``huggingface`` metadata in sorted-key JSON."""
    schema = features.arrow_schema
    meta = dict(schema.metadata or {})
    if b"huggingface" in meta:
        meta[b"huggingface"] = json.dumps(json.loads(meta[b"huggingface"]), sort_keys=True).encode()
    return schema.with_metadata(meta)


def write_shards(
    records: Iterable[dict[str, Any]],
    folder: Path,
    features: datasets.Features,
    names: Sequence[str],
    shard_rows: int,
    advance: Callable[[int], None] = lambda n: None,
) -> ShardWriter:
    """Write ``records`` to the shards ``names`` in ``folder``; ``advance(1)`` after each.

    Returns:
        The closed writer (``.rows``, ``.bytes`` on disk, ``.arrow_bytes`` in memory).
    """
    writer = ShardWriter(folder, features, names, shard_rows)
    for record in records:
        writer.add(record)
        advance(1)
    writer.close()
    return writer
