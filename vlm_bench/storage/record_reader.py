"""Reading episode records and cached responses back from a run folder."""

from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError

from vlm_bench.errors import DataFileError, first_problem
from vlm_bench.storage.jsonl import iter_jsonl
from vlm_bench.types.records import CachedResponse, EpisodeRecord, migrate_record


def _fail(path: Path, number: int, exc: ValidationError | ValueError) -> DataFileError:
    if isinstance(exc, ValidationError):
        where, why, _ = first_problem(exc)
        return DataFileError(str(path), f"line {number}: {where or '(record)'}: {why}")
    return DataFileError(str(path), f"line {number}: {exc}")


def read_records(path: Path) -> list[EpisodeRecord]:
    """Every record line of ``records.jsonl``, in file order (older layouts are migrated).

    Raises:
        DataFileError: A line that is not a valid record (names the file, line and field).
    """
    out: list[EpisodeRecord] = []
    for number, data in iter_jsonl(path):
        try:
            out.append(EpisodeRecord.model_validate(migrate_record(data)))
        except (ValidationError, ValueError) as exc:
            raise _fail(path, number, exc) from None
    return out


def latest_records(path: Path) -> list[EpisodeRecord]:
    """One record per episode key, the last written, in order of each key's first line.

    A resume appends a retried episode's new record after its error record; the new one wins.
    """
    latest: dict[str, EpisodeRecord] = {}
    for record in read_records(path):
        latest[record.key] = record
    return list(latest.values())


def read_responses(path: Path) -> dict[tuple[str, str], CachedResponse]:
    """The response cache: ``(episode key, prompt hash) -> response`` (last line wins).

    Raises:
        DataFileError: A line that is not a valid cached response.
    """
    out: dict[tuple[str, str], CachedResponse] = {}
    for number, data in iter_jsonl(path):
        try:
            resp = CachedResponse.model_validate(data)
        except ValidationError as exc:
            raise _fail(path, number, exc) from None
        out[(resp.key, resp.prompt_hash)] = resp
    return out
