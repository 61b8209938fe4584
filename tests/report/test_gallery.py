"""The HTML gallery: plan alignment, page content, and the page in headless Chromium."""

from __future__ import annotations

import importlib.util
import re
import shutil
from pathlib import Path

import pytest

from vlm_bench.report.gallery import write_gallery
from vlm_bench.report.plan_diff import failed_step, plan_diff
from vlm_bench.runner.run_views import run_views
from vlm_bench.types.parse import ParsedStep

GT = [
    {"subtask": 0, "tasktype": "UAV", "direction": "front"},
    {"subtask": 1, "tasktype": "ARM", "object": "cube", "skill": "pick"},
    {"subtask": 2, "tasktype": "UAV", "direction": "left", "distance": 0.5},
    {"subtask": 3, "tasktype": "ARM", "object": "basket", "skill": "place"},
]


def _uav(i: int, direction: str, distance: float | None = None) -> ParsedStep:
    return ParsedStep(
        index=i, tasktype="UAV", direction=direction, skill="move", distance=distance, valid=True
    )  # type: ignore[arg-type]


def _arm(i: int, skill: str, obj: str) -> ParsedStep:
    return ParsedStep(index=i, tasktype="ARM", skill=skill, object=obj, valid=True)


def _statuses(pred: list[ParsedStep]) -> list[str]:
    return [row.status for row in plan_diff(GT, pred)]


def test_plan_diff_aligns_changed_missing_and_extra_steps() -> None:
    same = [_uav(0, "front"), _arm(1, "pick", "cube"), _uav(2, "left"), _arm(3, "place", "basket")]
    assert _statuses(same) == ["same"] * 4  # the distance is ignored, as Succ ignores it
    wrong = [_uav(0, "back"), *same[1:]]
    rows = plan_diff(GT, wrong)
    assert [r.status for r in rows] == ["changed", "same", "same", "same"]
    assert (rows[0].gt, rows[0].pred) == ("UAV front", "UAV back")
    assert rows[2].gt == "UAV left 0.5 m"
    assert _statuses(same[:3]) == ["same", "same", "same", "missing"]
    extra = [*same[:2], _arm(2, "push", "cube"), _uav(3, "left"), _arm(4, "place", "basket")]
    assert _statuses(extra) == ["same", "same", "extra", "same", "same"]
    invalid = ParsedStep(index=0, tasktype=None, valid=False, raw={"tasktype": "UAV"})
    rows = plan_diff(GT, [invalid, *same[1:]])
    assert rows[0].status == "changed" and rows[0].pred == 'invalid: {"tasktype": "UAV"}'
    assert [r.pred_index for r in rows] == [0, 1, 2, 3]


def test_failed_step_reads_the_executors_reason() -> None:
    assert failed_step("step 2: unknown object 'green_cup'") == 2
    assert failed_step("goal not met: inside(banana, top_drawer)") is None
    assert failed_step(None) is None


def _gallery(real_runs: dict[str, Path], out: Path, inline: bool = False) -> str:
    page = write_gallery(real_runs["mock"], out, inline=inline, views=run_views(render=False))
    return page.read_text(encoding="utf-8")


def test_gallery_page_shows_every_episode_with_its_views(
    real_runs: dict[str, Path], tmp_path: Path
) -> None:
    html = _gallery(real_runs, tmp_path / "g")
    cards = re.findall(r'<article class="episode"[^>]*data-outcome="(\w+)"', html)
    assert len(cards) == 8 and {"exact", "inexact", "no_plan", "error"} <= set(cards)
    assert html.count('<img src="img/') == 8 * 4  # four views of every episode
    assert len(list((tmp_path / "g" / "img").glob("*.jpg"))) == 4 * 4  # shared by instructions
    assert 'class="changed"' in html and "wrong_direction" in html
    assert "mock: server timeout" in html
    assert not re.search(r'(src|href)="(https?:)?//', html)  # no external assets


def test_inline_gallery_is_one_file(real_runs: dict[str, Path], tmp_path: Path) -> None:
    html = _gallery(real_runs, tmp_path / "g", inline=True)
    assert html.count('src="data:image/jpeg;base64,') == 32
    assert [p.name for p in (tmp_path / "g").iterdir()] == ["index.html"]


def test_gallery_shows_a_recorded_video(real_runs: dict[str, Path], tmp_path: Path) -> None:
    run = tmp_path / "runs" / "mock"
    shutil.copytree(real_runs["mock"], run)
    (run / "videos").mkdir()
    (run / "videos" / "standard_pick_place_0_explicit.gif").write_bytes(b"GIF89a")
    page = write_gallery(run, tmp_path / "g", views=run_views(render=False))
    html = page.read_text(encoding="utf-8")
    assert 'src="videos/standard_pick_place_0_explicit.gif"' in html
    assert (tmp_path / "g" / "videos" / "standard_pick_place_0_explicit.gif").is_file()
    assert "no uav image" in html  # the copy has no snapshot cache beside it


def _browser() -> str:
    if importlib.util.find_spec("playwright") is None:
        pytest.skip("playwright is not installed (pip install 'vlm-bench[dev]')")
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if path := shutil.which(name):
            return path
    pytest.skip("no Chromium on this machine (apt-get install chromium)")


def test_gallery_in_headless_chromium(real_runs: dict[str, Path], tmp_path: Path) -> None:
    executable = _browser()
    from playwright.sync_api import sync_playwright

    page_path = write_gallery(real_runs["mock"], tmp_path / "g", views=run_views(render=False))
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=executable, args=["--no-sandbox"])
        try:
            page = browser.new_page()
            errors: list[str] = []
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(page_path.as_uri())
            page.wait_for_load_state("load")
            assert errors == []
            assert page.inner_text("#count") == "8 of 8 episodes"
            assert page.locator("article.episode:visible").count() == 8
            loaded = page.evaluate(
                "Array.from(document.images).filter(i => i.complete && i.naturalWidth > 0).length"
            )
            assert loaded == 32
            page.select_option("#f-outcome", "no_plan")
            visible = page.locator("article.episode:visible")
            assert visible.count() == 2 and page.inner_text("#count") == "2 of 8 episodes"
            assert all(visible.nth(i).get_attribute("data-outcome") == "no_plan" for i in range(2))
            page.select_option("#f-outcome", "")
            page.select_option("#f-code", "wrong_direction")
            assert 0 < page.locator("article.episode:visible").count() < 8
            assert errors == []
        finally:
            browser.close()


def test_planning_only_gallery_has_no_execution_legend(
    real_runs: dict[str, Path], tmp_path: Path
) -> None:
    html = _gallery(real_runs, tmp_path / "g")  # the mock run does not execute plans
    assert "step where execution failed" not in html and 'id="f-exec"' not in html


def _report_gallery(real_runs: dict[str, Path], out: Path) -> list[Path]:
    from vlm_bench.report import load, report_options
    from vlm_bench.report.gallery_index import write_galleries

    runs = tuple(str(real_runs[m]) for m in ("oracle", "random", "mock"))
    frame = load(*runs)
    options = report_options(runs=runs, render_missing=False)
    return write_galleries(frame, out, options, run_views(render=False))


def test_report_gallery_has_an_index_and_a_compare_page_per_episode(
    real_runs: dict[str, Path], tmp_path: Path
) -> None:
    written = _report_gallery(real_runs, tmp_path / "g")
    index = (tmp_path / "g" / "index.html").read_text(encoding="utf-8")
    assert tmp_path / "g" / "index.html" in written
    for run in ("oracle", "random", "mock"):
        assert f'href="{run}/index.html"' in index
    compare = sorted((tmp_path / "g" / "compare").glob("*.html"))
    assert len(compare) == 8  # 2 tasks x 2 seeds x 2 instructions
    html = (tmp_path / "g" / "compare" / "standard_pick_place_0_explicit.html").read_text()
    assert html.count('<section class="plan run">') == 3 and html.count("<img ") == 4
    assert html.count('src="../oracle/img/standard_pick_place_0_') == 4  # the views once
    run_page = (tmp_path / "g" / "mock" / "index.html").read_text(encoding="utf-8")
    assert 'href="../compare/standard_pick_place_0_explicit.html"' in run_page


def test_index_and_compare_pages_in_headless_chromium(
    real_runs: dict[str, Path], tmp_path: Path
) -> None:
    executable = _browser()
    from playwright.sync_api import sync_playwright

    _report_gallery(real_runs, tmp_path / "g")
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=executable, args=["--no-sandbox"])
        try:
            page = browser.new_page()
            errors: list[str] = []
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto((tmp_path / "g" / "index.html").as_uri())
            assert page.locator("#runs tbody tr").count() == 3
            assert page.locator("#episodes tbody tr").count() == 8
            page.click("text=standard_pick_place/0/explicit")
            page.wait_for_load_state("load")
            assert page.url.endswith("compare/standard_pick_place_0_explicit.html")
            assert page.locator("section.plan").count() == 4  # GT and three runs
            loaded = page.evaluate(
                "Array.from(document.images).filter(i => i.complete && i.naturalWidth > 0).length"
            )
            assert loaded == 4
            assert "UAV" in page.inner_text("#gt")
            page.click("section.run >> text=mock")
            page.wait_for_load_state("load")
            assert page.url.split("#")[0].endswith("mock/index.html")
            assert errors == []
        finally:
            browser.close()


def test_without_a_view_source_a_gallery_reads_the_run_folder_only(
    real_runs: dict[str, Path], tmp_path: Path
) -> None:
    html = write_gallery(real_runs["mock"], tmp_path / "g").read_text(encoding="utf-8")
    assert len(re.findall(r'<article class="episode"', html)) == 8
    assert "<img " not in html and not list((tmp_path / "g").rglob("*.jpg"))
