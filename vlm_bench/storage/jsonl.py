"""Append-only JSON Lines files that survive a crash mid-write.

Every line is written with one ``write`` call ending in a newline, then flushed and fsynced, so a
crash can only leave a *torn* last line: bytes after the last newline. Readers skip it; writers
cut it off (:func:`repair_tail`) before appending, so the file is valid JSONL again.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from vlm_bench.closing import ClosesOnExit
from vlm_bench.errors import DataFileError


def torn_tail(path: Path) -> int:
    """How many bytes follow the last newline of ``path`` (a torn last line); 0 when the file
    is missing, empty or intact. Reads only the end of the file."""
    if not path.exists():
        return 0
    with path.open("rb") as fh:
        size = fh.seek(0, os.SEEK_END)
        if size == 0:
            return 0
        fh.seek(size - 1)
        if fh.read(1) == b"\n":
            return 0
        # Walk back in blocks to the last newline; everything after it is torn.
        end = size
        while end > 0:
            start = max(0, end - 65536)
            fh.seek(start)
            nl = fh.read(end - start).rfind(b"\n")
            if nl >= 0:
                return size - (start + nl + 1)
            end = start
        return size


def repair_tail(path: Path) -> int:
    """Cut a torn last line (no trailing newline) off ``path``.

    Returns:
        The number of bytes removed (0 when the file is missing, empty or intact).
    """
    torn = torn_tail(path)
    if torn:
        with path.open("rb+") as fh:
            fh.truncate(fh.seek(0, os.SEEK_END) - torn)
            fh.flush()
            os.fsync(fh.fileno())
    return torn


def iter_jsonl(path: Path) -> Iterator[tuple[int, dict[str, Any]]]:
    """Yield ``(line number, object)`` for each complete line; a torn last line is skipped.

    Raises:
        DataFileError: A complete line that is not a JSON object (the file is corrupted);
            names the file and the line.
    """
    if not path.exists():
        return
    with path.open("rb") as fh:
        for number, raw in enumerate(fh, start=1):
            if not raw.endswith(b"\n"):
                return  # torn by a crash mid-write: the writer repairs it on resume
            if not raw.strip():
                continue
            try:
                obj = json.loads(raw)
            except (json.JSONDecodeError, UnicodeDecodeError) as exc:
                raise DataFileError(str(path), f"line {number}: invalid JSON ({exc})") from None
            if not isinstance(obj, dict):
                raise DataFileError(str(path), f"line {number}: expected a JSON object")
            yield number, obj


class JsonlWriter(ClosesOnExit):
    """Appends JSON objects to a file, one durable line each (flush + fsync per line)."""

    def __init__(self, path: Path, *, fsync: bool = True) -> None:
        self.path = path
        self.fsync = fsync
        repair_tail(path)
        self._fh: IO[bytes] | None = path.open("ab")
        self._failed = False

    def append(self, obj: dict[str, Any] | str) -> None:
        """Write one line: a dict (serialised here) or an already serialised JSON object."""
        if self._fh is None:
            raise ValueError(f"{self.path} is closed")
        text = obj if isinstance(obj, str) else json.dumps(obj, ensure_ascii=False)
        if "\n" in text:
            raise ValueError("a JSONL line must not contain a newline")
        with naming_the_file(self.path):
            try:
                self._fh.write(text.encode("utf-8") + b"\n")
                self._fh.flush()
                if self.fsync:
                    os.fsync(self._fh.fileno())
            except OSError:
                self._failed = True
                raise

    def close(self) -> None:
        """Close the file. Idempotent. After a failed write (a full disk) the bytes still
        buffered are dropped: the failure was raised by :meth:`append`, the line is torn at
        worst, and the next writer cuts it off."""
        fh, self._fh = self._fh, None
        if fh is None:
            return
        try:
            fh.close()
        except OSError:
            if not self._failed:
                raise


@contextmanager
def naming_the_file(path: Path, tmp: Path | None = None) -> Iterator[None]:
    """Re-raise an ``OSError`` without a file name (a full disk on ``write``), or naming the
    temporary file ``tmp`` written on the way to ``path``, naming ``path``: the file the user
    asked for."""
    try:
        yield
    except OSError as exc:
        if exc.filename is not None and (tmp is None or exc.filename != str(tmp)):
            raise
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc


def write_jsonl_atomic(path: Path, lines: list[str]) -> None:
    """Replace ``path`` with ``lines`` (serialised JSON objects) via a fsynced temporary file."""
    tmp = path.with_name(f".{path.name}.tmp")
    with naming_the_file(path, tmp):
        with tmp.open("wb") as fh:
            for line in lines:
                fh.write(line.encode("utf-8") + b"\n")
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)


def write_text_atomic(path: Path, text: str) -> None:
    """Replace ``path`` with ``text`` via a temporary file (readers never see half a file)."""
    tmp = path.with_name(f".{path.name}.tmp")
    with naming_the_file(path, tmp):
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
