"""The gallery across the runs of a report: each run's gallery, an index page and one compare
page per episode.

``<folder>/index.html`` lists the runs (settings, episodes, mean S_total, exact plans) with
links to their galleries, then every episode as a row with each run's S_total and outcome.
``<folder>/compare/<task>_<seed>_<instruction>.html`` shows one episode across the runs: the
instruction and the four views once (from the first run that has them; runs that saw other
resolutions or labels are named), the GT plan, and each run's predicted plan beside it, its
steps marked as in the run galleries (changed, missing, extra), with its scores and error tags.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from vlm_bench.report.gallery import (
    EXECUTIONS,
    OUTCOMES,
    Card,
    RunGallery,
    _environment,
    build_gallery,
)
from vlm_bench.report.plan_diff import gt_text
from vlm_bench.storage.jsonl import write_text_atomic
from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.task import SUITE_TITLES

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped, unused-ignore]

    from vlm_bench.report.gallery_views import ViewSources
    from vlm_bench.report.report_options import ReportOptions
    from vlm_bench.types.records import EpisodeRecord

INDEX_TEMPLATE = "gallery_index.html.j2"
COMPARE_TEMPLATE = "gallery_compare.html.j2"


def compare_name(card: Card) -> str:
    """File name of an episode's compare page."""
    r = card.record
    return f"{r.task_id}_{r.seed}_{r.variant}.html"


@dataclass(frozen=True)
class Column:
    """One run on a compare page: where its gallery is, and its card of the episode."""

    gallery: RunGallery
    folder: str
    card: Card | None


def _views(columns: list[Column]) -> tuple[dict[str, str], str | None]:
    """The episode's views once, from the first run that has any, as URLs from compare/."""
    for col in columns:
        if col.card is not None and col.card.views:
            urls = {
                v: u if u.startswith("data:") else f"../{col.folder}/{u}"
                for v, u in col.card.views.items()
            }
            return urls, col.gallery.name
    return {}, None


@dataclass(frozen=True)
class RunRow:
    """One run on the index page."""

    gallery: RunGallery
    folder: str
    episodes: int
    answered: int
    mean_total: float | None
    exact: float | None
    """Percent of answered episodes with an exact plan."""

    @classmethod
    def of(cls, gallery: RunGallery, folder: str) -> RunRow:
        """The row of one run's gallery."""
        scored = [c.record.scores for c in gallery.cards if c.record.scores is not None]
        n = len(scored)
        return cls(
            gallery,
            folder,
            len(gallery.cards),
            n,
            sum(s.s_total for s in scored) / n if n else None,
            100.0 * sum(s.succ for s in scored) / n if n else None,
        )


def _episode_order(record: EpisodeRecord) -> tuple[str, int, str]:
    return (record.task_id, record.seed, record.variant)


def write_index(folder: Path, galleries: list[RunGallery]) -> list[Path]:
    """Write the index page and the compare pages; returns their paths."""
    env = _environment()
    folders = [g.page.parent.name for g in galleries]
    first_cards = {c.record.key: c.record for g in galleries for c in g.cards}
    # By task, then seed, then instruction: the order a reader looks an episode up in.
    keys = sorted(first_cards, key=lambda k: _episode_order(first_cards[k]))
    by_key = [{c.record.key: c for c in g.cards} for g in galleries]
    (folder / "compare").mkdir(parents=True, exist_ok=True)
    written = []
    for key in keys:
        columns = [
            Column(g, f, cards.get(key))
            for g, f, cards in zip(galleries, folders, by_key, strict=True)
        ]
        first = next(c.card for c in columns if c.card is not None)
        views, source = _views(columns)
        sizes = {
            (c.gallery.manifest.config.resolution, c.gallery.manifest.config.labels)
            for c in columns
            if c.card is not None
        }
        page = folder / "compare" / compare_name(first)
        html = env.get_template(COMPARE_TEMPLATE).render(
            card=first,
            columns=columns,
            gt=[gt_text(s) for s in first.record.gt_plan],
            views=VIEWS,
            urls=views,
            source=source,
            mixed=len(sizes) > 1,
            suite_titles={s.value: t for s, t in SUITE_TITLES.items()},
            outcome_labels=OUTCOMES,
            execution_labels=EXECUTIONS,
        )
        write_text_atomic(page, html)
        written.append(page)
    rows = [(key, [cards.get(key) for cards in by_key]) for key in keys]
    index = folder / "index.html"
    html = env.get_template(INDEX_TEMPLATE).render(
        runs=[RunRow.of(g, f) for g, f in zip(galleries, folders, strict=True)],
        rows=rows,
        compare_name=compare_name,
        outcome_labels=OUTCOMES,
    )
    write_text_atomic(index, html)
    return [index, *written]


def write_galleries(
    frame: pd.DataFrame, folder: Path, options: ReportOptions, views: ViewSources | None = None
) -> list[Path]:
    """One gallery per run of the report in ``folder/<run>/``, an index over them all
    (``folder/index.html``) and a page per episode comparing the runs
    (``folder/compare/``); the views from ``views`` (none without)."""
    runs = frame.drop_duplicates("run")[["run", "run_dir"]].itertuples(index=False, name=None)
    galleries = [
        build_gallery(
            Path(run_dir),
            folder / str(run).replace("/", "_"),
            inline=options.inline_images,
            views=views,
            name=str(run),
        )
        for run, run_dir in runs
    ]
    return [*(g.page for g in galleries), *write_index(folder, galleries)]
