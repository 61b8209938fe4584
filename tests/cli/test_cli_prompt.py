"""``vlm-bench prompt``: the exact request a run sends for one episode, for every condition."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest
from PIL import Image

import vlm_bench
from vlm_bench.backends.backend import Backend
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult

if TYPE_CHECKING:
    from tests.conftest import Cli

TASK, SEED = "drawer_interaction", 3


class Capturing(Backend):
    """Answers nothing useful; keeps every request it was sent."""

    name = "capturing"

    def __init__(self) -> None:
        self.requests: list[GenerationRequest] = []

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        self.requests.extend(requests)
        return [GenerationResult(id=r.id, text="[]") for r in requests]


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"scene_as_text": True, "object_list": False, "k_shot": 0},
        {"images": False},
        {"views": ("overhead", "uav"), "generation": GenerationConfig(constrained=True)},
    ],
    ids=["default", "scene-as-text", "no-images", "views-constrained"],
)
def test_the_preview_is_the_request_a_run_sends(tmp_path: Path, options: dict[str, Any]) -> None:
    common: dict[str, Any] = {"resolution": 32, **options}
    backend = Capturing()
    vlm_bench.run(
        model="mock",
        tasks=(TASK,),
        seeds=(SEED,),
        instructions=("implicit",),
        execute=False,
        out=tmp_path / "run",
        backend=backend,
        snapshot_cache=tmp_path / "cache",
        **common,
    )
    (sent,) = backend.requests
    preview = vlm_bench.preview_prompt(TASK, SEED, "implicit", snapshot_cache=False, **common)
    assert preview.request == sent  # text, images, output schema and episode facts alike
    (record,) = vlm_bench.load_run(tmp_path / "run").records
    assert preview.prompt.prompt_hash == record.prompt_hash


def test_cli_prints_the_prompt_and_writes_the_views(cli: Cli, tmp_path: Path) -> None:
    out = tmp_path / "views"
    args = ["prompt", TASK, "--seed", str(SEED), "--resolution", "48", "--out", str(out)]
    done = cli.run(*args, "--views", "overhead,uav", "--no-snapshot-cache")
    assert done.returncode == 0, done.stderr
    text = done.stdout
    system, user = text.split("### user\n")
    assert system.startswith("### system\n") and "# The robot" in system
    assert user.index("<image:overhead>") < user.index("<image:uav>")
    assert "<image:wrist>" not in text and "<image:side>" not in text
    assert "Objects in the scene:" in user
    assert sorted(p.name for p in out.iterdir()) == ["overhead.png", "uav.png"]
    with Image.open(out / "uav.png") as image:
        assert image.size == (48, 48)
    assert "prompt hash " in done.stderr and f"wrote {out / 'uav.png'}" in done.stderr


def test_cli_conditions_change_the_prompt(cli: Cli, tmp_path: Path) -> None:
    base = ["prompt", TASK, "--seed", str(SEED), "--resolution", "32", "--no-snapshot-cache"]
    plain = cli.invoke(*base, "--no-images")
    assert "<image:" not in plain and "Objects in the scene:" in plain
    text = cli.invoke(*base, "--scene-as-text", "--no-object-list", "--k-shot", "0")
    assert "# The scene as text" in text and "Objects in the scene:" not in text
    assert "Example 1" not in text
    implicit = cli.invoke(*base, "--instruction", "implicit", "--no-images")
    assert implicit.split("Instruction:")[-1] != plain.split("Instruction:")[-1]
    schema = cli.invoke(*base, "--no-images", "--constrained")
    assert "### output schema (constrained decoding)" in schema


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["no_such_task"], "unknown task 'no_such_task'"),
        ([TASK, "--views", "top"], "unknown camera view 'top'"),
        ([TASK, "--instruction", "both"], "unknown instruction variant 'both'"),
        ([TASK, "--k-shot", "99", "--no-images"], "k_shot"),
    ],
)
def test_cli_bad_options_are_one_line(cli: Cli, args: list[str], message: str) -> None:
    done = cli.run("prompt", *args)
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], lines


def test_run_and_prompt_share_one_option_set_with_the_run_configs_defaults() -> None:
    import inspect

    from vlm_bench.cli.prompt_cmd import prompt
    from vlm_bench.cli.run_cmds import run
    from vlm_bench.types.run import RunConfig

    config = RunConfig(model="oracle")
    expected = {
        "views": ",".join(config.views),
        "resolution": config.resolution,
        "k_shot": config.k_shot,
        "no_object_list": not config.object_list,
        "no_images": not config.images,
        "scene_as_text": config.scene_as_text,
        "no_snapshot_cache": False,
    }
    run_params = inspect.signature(run).parameters
    prompt_params = inspect.signature(prompt).parameters
    for name, default in expected.items():
        assert run_params[name].default == prompt_params[name].default == default, name
        assert run_params[name].annotation == prompt_params[name].annotation, name
    assert run_params["batch_size"].default == config.generation.batch_size
    assert run_params["max_new_tokens"].default == config.generation.max_new_tokens
    assert run_params["temperature"].default == config.generation.temperature
    for name in ("execute", "uav_noise", "loop", "max_rounds", "history"):
        assert run_params[name].default == getattr(config, name), name
