"""End-to-end CLI: run (oracle ceiling, random floor), refusals, rescore, score."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import pytest
from filelock import FileLock

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import get_episode
from vlm_bench.storage import latest_records
from vlm_bench.types.plan import UavStep, plan_to_json

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
FEW = ("standard_pick_place", "target_color_yellow", "synonym_block_bin", "tower_stacking")
METRICS = ["S_plan", "S_loc", "S_obj", "S_skill", "S_total", "Succ"]


def _run_args(
    cli: Cli, out: Path, model: str, tasks: tuple[str, ...], seeds: str = "0-1"
) -> list[str]:
    # Plan execution is tested in test_cli_execute.py; these runs are about planning.
    return cli.run_args(out, model, tasks, seeds, "--resolution", "64", "--no-execute")


def test_oracle_run_scores_100_everywhere(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "oracle"
    printed = cli.invoke(*_run_args(cli, out, "oracle", FEW))
    summary = pd.read_csv(out / "summary.csv")
    assert set(summary.instruction) == {"explicit", "implicit", "both"}
    assert set(summary.suite) == {
        "base_manipulation",
        "object_spatial",
        "semantic_understanding",
        "long_horizon",
        "overall",
    }
    assert (summary[METRICS] == 100.0).all().all(), summary
    overall = summary[(summary.instruction == "both") & (summary.suite == "overall")].iloc[0]
    assert overall.n == len(FEW) * 2 * 2 and overall.n_error == 0
    records = latest_records(out / "records.jsonl")
    assert len(records) == 16 and all(
        r.parse is not None and r.parse.tier == "valid" for r in records
    )
    assert "Overall" in printed and "summary.md" in printed
    # Not a terminal: the table is as wide as it needs (suite names in full), rows unwrapped.
    assert re.search(r"oracle\s+explicit\s+Base Manipulation", printed), printed
    assert (out / "summary.md").read_text().count("| oracle |") == 3


@pytest.mark.parametrize("env", ["FORCE_COLOR", "TTY_COMPATIBLE"])
def test_a_redirected_summary_is_not_wrapped_when_colour_is_forced(
    cli: Cli, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, env: str
) -> None:
    # rich calls a redirected stream a terminal under these variables (as in a CI log or a
    # nohup shell); the summary still takes its width from the stream, not 80 columns.
    monkeypatch.setenv(env, "1")
    printed = cli.invoke(*_run_args(cli, tmp_path / "run", "oracle", FEW[:1], seeds="0"))
    assert re.search(r"│ oracle │ explicit │( 100\.0 │){6}", printed), printed
    assert "\x1b[" not in printed  # a log file gets no colour codes


def test_random_run_scores_far_below(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "random"
    cli.invoke(*_run_args(cli, out, "random", FEW))
    summary = pd.read_csv(out / "summary.csv")
    overall = summary[(summary.instruction == "both") & (summary.suite == "overall")].iloc[0]
    assert overall.S_total < 60.0 and overall.Succ <= 10.0, overall


def test_perception_conditions_through_the_cli(cli: Cli, tmp_path: Path) -> None:
    """--scene-as-text with the rules planner is perfect; --no-images sends no image; the
    records carry the shuffled object order and whether the first target was in view."""
    out = tmp_path / "rules"
    printed = cli.invoke(*_run_args(cli, out, "rules", FEW), "--scene-as-text", "--no-images")
    summary = pd.read_csv(out / "summary.csv")
    assert (summary[METRICS] == 100.0).all().all(), summary
    assert "ΔLoc" in printed
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["config"]["scene_as_text"] is True and manifest["config"]["images"] is False
    records = latest_records(out / "records.jsonl")
    for record in records:
        episode = get_episode(record.task_id, record.seed)
        assert sorted(record.object_order) == sorted(episode.object_ids())
        assert isinstance(record.first_target_visible, bool)
    assert not (tmp_path / ".snapshots").exists() or not any((tmp_path / ".snapshots").iterdir())


@pytest.mark.slow
def test_oracle_full_sweep_all_60_tasks(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "full"
    cli.invoke(
        "run",
        "--model",
        "oracle",
        "--seeds",
        "0-1",
        "--resolution",
        "32",
        "--out",
        str(out),
        "--no-progress",
        "--batch-size",
        "16",
        "--no-execute",
    )
    summary = pd.read_csv(out / "summary.csv")
    assert (summary[METRICS] == 100.0).all().all()
    overall = summary[(summary.instruction == "both") & (summary.suite == "overall")].iloc[0]
    assert overall.n == len(all_tasks()) * 2 * 2 == 240


def test_mismatched_config_and_second_writer_are_refused(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    cli.invoke(*_run_args(cli, out, "oracle", FEW[:1], seeds="0"))
    refused = cli.run(
        *_run_args(cli, out, "oracle", FEW[:1], seeds="0-1"), "--max-new-tokens", "64"
    )
    assert refused.returncode == 2
    lines = refused.stderr.strip().splitlines()
    assert len(lines) == 1 and "different configuration" in lines[0], refused.stderr
    assert "seeds" in lines[0] and "generation.max_new_tokens" in lines[0]
    lock = FileLock(str(out / ".lock"), timeout=0)
    with lock:
        locked = cli.run(*_run_args(cli, out, "oracle", FEW[:1], seeds="0"))
    assert locked.returncode == 2
    assert locked.stderr.strip().startswith("error: ") and "another vlm-bench process" in (
        locked.stderr
    )
    assert len(locked.stderr.strip().splitlines()) == 1
    assert len(latest_records(out / "records.jsonl")) == 2


def test_rescore_command_rewrites_records_and_summary(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "run"
    cli.invoke(*_run_args(cli, out, "oracle", FEW[:2], seeds="0"))
    before = [r.without_timing() for r in latest_records(out / "records.jsonl")]
    (out / "summary.csv").unlink()
    printed = cli.invoke("rescore", str(out))
    assert "0 record(s) changed" in printed
    assert [r.without_timing() for r in latest_records(out / "records.jsonl")] == before
    assert (pd.read_csv(out / "summary.csv")[METRICS] == 100.0).all().all()


def test_a_torn_last_record_line_is_reported_then_healed_by_rescore(
    cli: Cli, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    cli.invoke(*_run_args(cli, out, "oracle", FEW[:1], seeds="0"))
    records = out / "records.jsonl"
    lines = records.read_bytes().splitlines(keepends=True)
    records.write_bytes(b"".join(lines[:-1]) + lines[-1][:40])  # a crash mid-write
    reported = cli.run("report", str(out), "--no-stats")
    assert reported.returncode == 0, reported.stderr
    assert f"{records} ends in a torn line (40 bytes" in reported.stderr
    rescored = cli.run("rescore", str(out), "--no-progress")
    assert rescored.returncode == 0, rescored.stderr
    said = " ".join(rescored.stdout.split())
    assert "records.jsonl ended in a torn line (40 bytes" in said and "re-run the run" in said
    assert records.read_bytes() == b"".join(lines[:-1])  # healed: whole lines only
    resumed = cli.run(*_run_args(cli, out, "oracle", FEW[:1], seeds="0"))
    assert resumed.returncode == 0 and len(latest_records(records)) == 2


def test_score_command_json(cli: Cli, tmp_path: Path) -> None:
    episode = get_episode("standard_pick_place", 1)
    gt = plan_to_json(episode.gt_plan)
    first_move = next(i for i, s in enumerate(episode.gt_plan) if isinstance(s, UavStep))
    step = episode.gt_plan[first_move]
    assert isinstance(step, UavStep) and step.direction.is_horizontal
    order = ["front", "frontleft", "left", "backleft", "back", "backright", "right", "frontright"]
    neighbour = order[(order.index(step.direction.value) + 1) % 8]
    predicted = [dict(s) for s in gt]
    predicted[first_move]["direction"] = neighbour
    output = tmp_path / "out.txt"
    output.write_text("Sure! Here is the plan:\n```json\n" + json.dumps(predicted) + "\n```\n")
    data = json.loads(
        cli.invoke(
            "score",
            "standard_pick_place",
            "--seed",
            "1",
            "--instruction",
            "implicit",
            "--output",
            str(output),
            "--json",
        )
    )
    assert (data["task_id"], data["seed"], data["instruction"]) == (
        "standard_pick_place",
        1,
        "implicit",
    )
    assert data["parse"]["tier"] == "repaired" and data["gt_plan"] == gt
    n_move = sum(s["tasktype"] == "UAV" for s in gt)
    scores = data["scores"]
    assert scores["s_loc"] == pytest.approx((40.0 + 100.0 * (n_move - 1)) / n_move)
    assert scores["s_plan"] == scores["s_obj"] == scores["s_skill"] == 100.0
    assert scores["succ"] is False and "wrong_direction" in data["error_tags"]
    assert data["plan"] == predicted
    text = cli.invoke("score", "standard_pick_place", "--seed", "1", "--output", str(output))
    assert "wrong_direction" in text and "repaired" in text


def test_score_command_user_errors_are_one_line(cli: Cli, tmp_path: Path) -> None:
    missing = cli.run("score", "standard_pick_place", "--output", str(tmp_path / "nope.txt"))
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1
    assert "cannot read" in missing.stderr
    bad_task = cli.run("score", "no_such_task", "--output", str(ROOT / "pyproject.toml"))
    assert bad_task.returncode == 2 and "unknown task 'no_such_task'" in bad_task.stderr


def test_run_option_errors_are_one_line(cli: Cli, tmp_path: Path) -> None:
    bad = cli.run("run", "--model", "oracle", "--views", "uav,top", "--out", str(tmp_path / "x"))
    assert bad.returncode == 2 and "unknown camera view 'top'" in bad.stderr
    both = cli.run(
        "run",
        "--model",
        "oracle",
        "--task",
        "standard_pick_place",
        "--suite",
        "lh",
        "--out",
        str(tmp_path / "y"),
    )
    assert both.returncode == 2 and "not both" in both.stderr
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


def test_planning_help_and_api_import_stay_light() -> None:
    code = (
        "import sys\n"
        "from typer.testing import CliRunner\n"
        "from vlm_bench.cli.main import app, _register\n"
        "import vlm_bench.api\n"
        "_register()\n"
        "for cmd in ('run', 'rescore', 'score', 'execute'):\n"
        "    r = CliRunner().invoke(app, [cmd, '--help'])\n"
        "    assert r.exit_code == 0, r.output\n"
        "heavy = ('torch', 'transformers', 'mujoco', 'pandas', 'vlm_bench.sim',\n"
        "         'vlm_bench.runner')\n"
        "print(','.join(m for m in heavy if m in sys.modules))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "", f"imported: {result.stdout}"


def test_a_run_the_backend_never_answers_exits_3_and_says_how_to_retry(
    cli: Cli, tmp_path: Path
) -> None:
    script = tmp_path / "answers.jsonl"
    script.write_text("")  # the mock answers no id: every request fails in the backend
    out = tmp_path / "run"
    args = cli.run_args(out, "mock", ("standard_pick_place",), "0-1", "--resolution", "32")
    failed = cli.run(*args, "--no-execute", "-M", f"file={script}")
    assert failed.returncode == 3, failed.stderr
    said = " ".join(failed.stdout.split())
    assert "4 of 4 episode(s) have no result" in said and "re-run the same command" in said
    answered = '{"id": "%s", "text": "[{\\"tasktype\\": \\"UAV\\", \\"direction\\": \\"up\\"}]"}'
    keys = [f"standard_pick_place/{s}/{v}" for s in (0, 1) for v in ("explicit", "implicit")]
    script.write_text("\n".join(answered % k for k in keys) + "\n")
    retried = cli.run(*args, "--no-execute", "-M", f"file={script}")
    assert retried.returncode == 0, retried.stdout + retried.stderr


def test_help_lists_the_exit_codes(cli: Cli) -> None:
    for command in ((), ("run",)):
        text = " ".join(cli.invoke(*command, "--help").split())
        assert "Exit codes: 0 done" in text and "3 run finished" in text and "143" in text


def test_a_ray_client_address_is_a_one_line_error(cli: Cli, tmp_path: Path) -> None:
    pytest.importorskip("ray", reason="the ray extra is not installed")
    out = tmp_path / "run"
    args = cli.run_args(out, "oracle", FEW[:1], "0", "--exec-backend", "ray")
    refused = cli.run(*args, "--ray-address", "ray://head:10001")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
    assert "Ray Client addresses are not supported" in refused.stderr
    assert not out.exists()
