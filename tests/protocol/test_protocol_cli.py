"""``--protocol`` end to end: the run says which protocol it is, in every file it writes."""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from vlm_bench.storage import RunPaths, read_manifest

if TYPE_CHECKING:
    from tests.conftest import Cli

TASK = "standard_pick_place"


def _csv(output: str) -> pd.DataFrame:
    """The CSV table of a report's output (its warnings, on stderr, left out)."""
    lines = [line for line in output.splitlines() if not line.startswith("warning: ")]
    return pd.read_csv(io.StringIO("\n".join(lines)))


def test_a_protocol_run_records_and_prints_its_share(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "paper"
    args = cli.run_args(out, "oracle", [TASK], "0", "--protocol", "paper", "--no-execute")
    printed = cli.invoke(*args)
    # One task × seed 0 × both instructions of the protocol's 60 × 10 × 2 episodes.
    assert "protocol: paper (2 of 1,200 episodes, 0.2%)" in printed
    manifest = read_manifest(RunPaths(out))
    assert manifest.protocol is not None and manifest.protocol.name == "paper"
    assert manifest.config.instructions == ("explicit", "implicit")
    assert manifest.config.resolution == 448
    assert "Protocol: paper (2 of 1,200 episodes, 0.2%)" in (out / "summary.md").read_text()
    assert set(pd.read_csv(out / "summary.csv")["protocol"]) == {
        "paper (2 of 1,200 episodes, 0.2%)"
    }
    results = json.loads((out / "results.json").read_text())
    assert results["protocol"] == {"name": "paper", "episodes": 2, "protocol_episodes": 1200}


def test_a_run_off_every_protocol_is_custom_in_every_file(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "custom"
    printed = cli.invoke(*cli.run_args(out, "oracle", [TASK], "0", "--resolution", "64"))
    assert "protocol: custom" in printed
    assert "Protocol: custom" in (out / "summary.md").read_text()
    assert set(pd.read_csv(out / "summary.csv")["protocol"]) == {"custom"}
    assert json.loads((out / "results.json").read_text())["protocol"]["name"] == "custom"


def test_protocol_refuses_an_option_it_fixes(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "refused"
    args = cli.run_args(out, "oracle", [TASK], "0", "--protocol", "paper", "--resolution", "64")
    done = cli.run(*args, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [
        "error: --protocol paper sets --resolution to 448; drop --resolution or --protocol"
    ]
    assert not out.exists()  # nothing half-written
    unknown = cli.run(*cli.run_args(out, "oracle", [TASK], "0", "--protocol", "open"))
    assert unknown.returncode == 2 and "valid: closed, custom, paper" in unknown.stderr


def test_reports_say_when_runs_of_different_protocols_are_pooled(cli: Cli, tmp_path: Path) -> None:
    paper, custom = tmp_path / "paper", tmp_path / "custom"
    cli.invoke(*cli.run_args(paper, "oracle", [TASK], "0", "--no-execute"))
    cli.invoke(*cli.run_args(custom, "oracle", [TASK], "0", "--no-execute", "--k-shot", "0"))
    markdown = cli.invoke("report", str(paper), str(custom), "-f", "markdown", "--no-stats")
    assert "Protocols: paper: paper (2 of 1,200 episodes, 0.2%); custom: custom." in markdown
    assert "Runs of different protocols (paper: paper; custom: custom)" in markdown
    assert "Row oracle pools runs of protocols paper and custom" in markdown
    csv = cli.invoke("report", str(paper), str(custom), "-f", "csv", "--no-stats")
    assert set(_csv(csv)["protocol"]) == {"paper+custom"}
    latex = cli.invoke("report", str(paper), str(custom), "-f", "latex", "--no-stats")
    assert "Runs of different protocols" in latex and "custom" in latex
    apart = cli.invoke("report", str(paper), str(custom), "-f", "csv", "--no-stats", "--by", "run")
    assert set(_csv(apart)["protocol"]) == {"paper", "custom"}


def test_the_python_api_takes_a_protocol(tmp_path: Path) -> None:
    import vlm_bench

    result = vlm_bench.run(
        model="oracle", protocol="closed", tasks=(TASK,), seeds=(0,), out=tmp_path / "run"
    )
    config = result.manifest.config
    assert config.loop == "closed" and config.max_rounds == 3
    assert config.perturb is not None and (config.perturb.slip, config.perturb.bump) == (0.3, 0.3)
    assert config.instructions == ("explicit", "implicit") and config.seeds == (0,)
    assert result.manifest.protocol is not None and result.manifest.protocol.name == "closed"
    results = json.loads((tmp_path / "run" / "results.json").read_text())
    assert results["loop"] == "closed"
    assert [s["k"] for s in results["succ_at_k"] if s["instruction"] == "both"] == [0, 1, 2, 3]
