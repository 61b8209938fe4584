"""A static HTML gallery of a run's episodes: ``<folder>/<run>/index.html``.

One self-contained page per run: no server, no external assets, no network. Each episode shows
the four camera views, the instruction, the GT and predicted plans side by side with differing
steps highlighted (:mod:`vlm_bench.report.plan_diff`), the error tags, the scores and the
execution outcome with the failing step's reason. Filters (suite, outcome, execution, error code)
run in a few lines of inline JavaScript. Images are JPEG files in ``img/`` beside the page, or
inside it as data URLs (``inline``). A video is shown when the run folder holds one at
``videos/<task_id>_<seed>_<instruction>.{mp4,webm,gif}``.
"""

from __future__ import annotations

import base64
import shutil
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import jinja2

from vlm_bench.report.gallery_rounds import RoundCard, attach_round_views, round_cards
from vlm_bench.report.gallery_views import to_jpeg
from vlm_bench.report.plan_diff import DiffRow, failed_step, plan_diff
from vlm_bench.storage import RunPaths, latest_records, read_manifest
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.records import EpisodeRecord
from vlm_bench.types.run import RunManifest
from vlm_bench.types.task import SUITE_TITLES

if TYPE_CHECKING:
    from vlm_bench.report.gallery_views import ViewSource, ViewSources

TEMPLATE = "gallery.html.j2"
VIDEO_TYPES = {".mp4": "video/mp4", ".webm": "video/webm", ".gif": "image/gif"}
OUTCOMES = {
    "exact": "exact plan",
    "inexact": "inexact plan",
    "no_plan": "no plan",
    "error": "backend error",
}
EXECUTIONS = {"success": "succeeded", "failed": "failed", "not_executed": "not executed"}


@dataclass
class Card:
    """What the page shows of one episode."""

    record: EpisodeRecord
    instruction: str
    outcome: str
    execution: str
    rows: list[DiffRow]
    failed_index: int | None
    views: dict[str, str] = field(default_factory=dict)
    """View → image URL (file name or data URL)."""
    video: tuple[str, str] | None = None
    """(URL, MIME type)."""
    rounds: list[RoundCard] = field(default_factory=list)
    """A closed-loop episode's replans."""

    @property
    def codes(self) -> str:
        """Space-separated error tags (the filter's attribute)."""
        return " ".join(self.record.error_tags)


def outcome_of(record: EpisodeRecord) -> str:
    """``error`` (backend), ``no_plan`` (invalid output), ``exact`` or ``inexact``."""
    if not record.ok or record.scores is None:
        return "error"
    if record.parse is not None and not record.parse.usable:
        return "no_plan"
    return "exact" if record.scores.succ else "inexact"


def execution_of(record: EpisodeRecord, executes: bool) -> str:
    """``success``, ``failed``, ``not_executed`` or ``off`` (the run executes no plans)."""
    if not executes:
        return "off"
    if record.execution is None:
        return "not_executed"
    return "success" if record.execution.exec_success else "failed"


def _failed_parse_index(record: EpisodeRecord) -> int | None:
    # Execution numbers the executed (valid) steps; the table numbers the model's steps.
    k = failed_step(record.execution.failure_reason if record.execution else None)
    if k is None or record.parse is None:
        return None
    valid = [s.index for s in record.parse.steps if s.valid]
    return valid[k] if k < len(valid) else None


def _url(data: bytes, mime: str, name: str, folder: Path, inline: bool) -> str:
    if inline:
        return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"
    (folder / name).write_bytes(data)
    return name


def _video(run_dir: Path, record: EpisodeRecord, out: Path, inline: bool) -> tuple[str, str] | None:
    stem = f"{record.task_id}_{record.seed}_{record.variant}"
    for suffix, mime in VIDEO_TYPES.items():
        source = run_dir / "videos" / f"{stem}{suffix}"
        if source.is_file():
            if inline:
                return _url(source.read_bytes(), mime, "", out, True), mime
            (out / "videos").mkdir(exist_ok=True)
            shutil.copyfile(source, out / "videos" / source.name)
            return f"videos/{source.name}", mime
    return None


def cards(records: Iterable[EpisodeRecord], manifest: RunManifest) -> list[Card]:
    """The episodes of a run as cards (no images yet)."""
    from vlm_bench.catalog.tasks import get_task

    out = []
    for record in records:
        task = get_task(record.task_id)
        steps = record.parse.steps if record.parse is not None else ()
        out.append(
            Card(
                record=record,
                instruction=getattr(task.instructions, record.variant),
                outcome=outcome_of(record),
                execution=execution_of(record, manifest.config.execute),
                rows=plan_diff(record.gt_plan, steps),
                failed_index=_failed_parse_index(record),
                rounds=round_cards(record),
            )
        )
    return out


def _attach_media(
    items: list[Card], run_dir: Path, out: Path, views: ViewSource | None, inline: bool
) -> None:
    done: dict[tuple[str, int], dict[str, str]] = {}
    if not inline:
        (out / "img").mkdir(parents=True, exist_ok=True)
    for card in items:
        scene = (card.record.task_id, card.record.seed)
        if scene not in done:  # the two instruction variants share the scene
            pngs = views.start_views(*scene) if views is not None else {}
            done[scene] = {
                v: _url(
                    to_jpeg(png), "image/jpeg", f"img/{scene[0]}_{scene[1]}_{v}.jpg", out, inline
                )
                for v in VIEWS
                if (png := pngs.get(v)) is not None
            }
        card.views = done[scene]
        card.video = _video(run_dir, card.record, out, inline)
        if card.rounds and views is not None:
            _attach_rounds(card, views, out, inline)


def _attach_rounds(card: Card, views: ViewSource, out: Path, inline: bool) -> None:
    stem = f"img/{card.record.key.replace('/', '_')}"

    def url(round_index: int, view: str, data: bytes) -> str:
        return _url(data, "image/jpeg", f"{stem}_r{round_index}_{view}.jpg", out, inline)

    attach_round_views(card.record, card.rounds, views, url)


@cache
def _environment() -> jinja2.Environment:
    loader = jinja2.FileSystemLoader(str(Path(__file__).parent))
    return jinja2.Environment(loader=loader, autoescape=True, undefined=jinja2.StrictUndefined)


def render_page(
    title: str, manifest: RunManifest, items: list[Card], index: str | None = None
) -> str:
    """The gallery page (HTML text) of one run; ``index`` links back to the report's index."""
    suites = list(dict.fromkeys(c.record.suite for c in items))
    codes = sorted({t for c in items for t in c.record.error_tags})
    seen_views = set(manifest.config.views) if manifest.config.images else set()
    context: dict[str, Any] = {
        "title": title,
        "manifest": manifest,
        "cards": items,
        "suites": [(s.value, SUITE_TITLES[s]) for s in suites],
        "outcomes": [(k, v) for k, v in OUTCOMES.items() if any(c.outcome == k for c in items)],
        "executions": [
            (k, v) for k, v in EXECUTIONS.items() if any(c.execution == k for c in items)
        ],
        "codes": codes,
        "views": VIEWS,
        "seen_views": seen_views,
        "suite_titles": {s.value: t for s, t in SUITE_TITLES.items()},
        "outcome_labels": OUTCOMES,
        "execution_labels": {**EXECUTIONS, "off": "not executed (planning-only run)"},
        "executes": manifest.config.execute,
        "index": index,
    }
    return _environment().get_template(TEMPLATE).render(**context)


@dataclass
class RunGallery:
    """One run's gallery as written: its page, settings and episode cards."""

    name: str
    page: Path
    manifest: RunManifest
    cards: list[Card]


def build_gallery(
    run_dir: Path,
    out: Path,
    inline: bool = False,
    views: ViewSources | None = None,
    name: str | None = None,
) -> RunGallery:
    """Write ``out/index.html`` (and ``out/img/``) for one run folder, its views from
    ``views`` (none without)."""
    paths = RunPaths(run_dir)
    manifest = read_manifest(paths)
    items = cards(latest_records(paths.records), manifest)
    out.mkdir(parents=True, exist_ok=True)
    source = views(run_dir, manifest) if views is not None else None
    try:
        _attach_media(items, run_dir, out, source, inline)
    finally:
        if source is not None:
            source.close()
    page = out / "index.html"
    index = "../index.html" if name is not None else None
    write_text_atomic(page, render_page(name or run_dir.name, manifest, items, index))
    return RunGallery(name or run_dir.name, page, manifest, items)


def write_gallery(
    run_dir: Path, out: Path, inline: bool = False, views: ViewSources | None = None
) -> Path:
    """Write ``out/index.html`` (and ``out/img/``) for one run folder; returns the page."""
    return build_gallery(run_dir, out, inline, views).page
