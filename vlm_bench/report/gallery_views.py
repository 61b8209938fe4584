"""Where a gallery's views come from, and their encoding.

Reports read run folders only, and a run folder keeps no views: an episode's start views are in
the shared snapshot cache and a replan's views in no file. Whoever asks for a gallery passes a
:data:`ViewSources` (the CLI's ``report`` passes :func:`vlm_bench.runner.run_views.run_views`,
which reads the cache and renders what is missing); without one, a gallery shows no views.
JPEG keeps a gallery of hundreds of episodes to a few dozen megabytes.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from PIL import Image

from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunManifest

JPEG_QUALITY = 85


def to_jpeg(png: bytes) -> bytes:
    """PNG bytes re-encoded as JPEG."""
    with Image.open(io.BytesIO(png)) as image:
        out = io.BytesIO()
        image.convert("RGB").save(out, format="JPEG", quality=JPEG_QUALITY)
        return out.getvalue()


class ViewSource(Protocol):
    """PNG views of one run's episodes, by view name (only those it has)."""

    def start_views(self, task_id: str, seed: int) -> dict[str, bytes]:
        """The views of an episode at its start (what the first prompt showed)."""
        ...

    def round_views(self, record: EpisodeRecord, round_index: int) -> dict[str, bytes]:
        """The views a closed-loop episode's replan ``round_index`` showed."""
        ...

    def close(self) -> None:
        """Release what the source holds (a renderer)."""
        ...


ViewSources = Callable[[Path, RunManifest], ViewSource]
"""Opens the view source of one run folder, given the folder and its manifest."""
