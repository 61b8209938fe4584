"""Bad input anywhere in the CLI: one line on stderr, a non-zero exit, no traceback, and nothing
written (a failed start leaves no run folder, so the corrected command starts clean)."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from importlib.util import find_spec
from pathlib import Path
from typing import TYPE_CHECKING

import pytest
from pydantic import ValidationError

import vlm_bench
from vlm_bench.backends import Backend
from vlm_bench.catalog.files import load_model
from vlm_bench.cli.main import _register, app, main
from vlm_bench.errors import ConfigError, DataFileError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.run import RunConfig, RunManifest
from vlm_bench.types.scores import ScoringConfig
from vlm_bench.types.skill import SkillSpec
from vlm_bench.types.task import TaskSpec

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
TASK = "standard_pick_place"


def _main(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    """Run the console entry point in this process: (exit code, stderr). An exception other
    than SystemExit fails the test: the real entry point would print its traceback."""
    with pytest.raises(SystemExit) as exit_info:
        main(list(args))
    code = exit_info.value.code
    return (code if isinstance(code, int) else 1), capsys.readouterr().err


def _one_line_error(code: int, err: str, *needles: str) -> str:
    assert code != 0, err
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    for needle in needles:
        assert needle in lines[0], lines[0]
    return lines[0]


def _run(out: Path, *extra: str, model: Sequence[str] = ("--model", "oracle")) -> list[str]:
    return [
        "run",
        *model,
        "--task",
        TASK,
        "--seeds",
        "0",
        "--no-images",
        "--no-execute",
        "--no-progress",
        "--out",
        str(out),
        *extra,
    ]


# Finite numbers only ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (("--uav-noise", "inf"), "--uav-noise"),
        (("--uav-noise", "nan"), "--uav-noise"),
        (("--temperature", "inf"), "--temperature"),
        (("--temperature", "nan"), "--temperature"),
        (("--model", "random", "-M", "seed=nan"), "seed"),
    ],
)
def test_run_refuses_non_finite_numbers_before_writing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: tuple[str, ...], needle: str
) -> None:
    out = tmp_path / "run"
    args = _run(out, *extra)
    if "--execute" not in args and extra[0] == "--uav-noise":
        args[args.index("--no-execute")] = "--execute"
    code, err = _main(capsys, *args)
    _one_line_error(code, err, needle)
    assert not out.exists()


@pytest.mark.skipif(find_spec("openai") is None, reason="needs the openai extra")
def test_backend_arguments_must_be_finite(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    model = ("--model", "openai/served", "-M", "timeout_s=inf")
    code, err = _main(capsys, *_run(out, model=model))
    _one_line_error(code, err, "timeout_s=inf", "finite")
    assert not out.exists()


@pytest.mark.parametrize(
    "extra", [("--uav-noise", "nan"), ("--uav-noise", "inf"), ("--fps", "nan")]
)
def test_execute_refuses_non_finite_numbers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: tuple[str, ...]
) -> None:
    video = tmp_path / "v.gif"
    code, err = _main(capsys, "execute", TASK, "--video", str(video), *extra)
    _one_line_error(code, err, extra[0], "finite")
    assert not video.exists()


def test_configs_written_to_disk_hold_finite_numbers_only() -> None:
    for bad in (math.inf, math.nan):
        with pytest.raises(ValidationError):
            RunConfig(model="oracle", uav_noise=bad)
        nested = ScoringConfig.model_construct(alpha=bad)
        with pytest.raises(ValidationError, match=r"scoring\.alpha must be a finite number"):
            RunConfig(model="oracle", scoring=nested)
    config = RunConfig(model="oracle", uav_noise=1.5)
    text = json.dumps({"run_id": "r", "config": config.model_dump(mode="json")})
    assert "Infinity" not in text and "NaN" not in text
    data = json.loads(text)
    data["config"]["uav_noise"] = math.inf
    with pytest.raises(ValidationError):
        RunManifest.model_validate(data)


# Validation before anything is written ------------------------------------------------------


@pytest.mark.parametrize(
    ("model", "needles"),
    [
        (("--model", "mock", "-M", "bogus=1"), ("'bogus'", "valid: file, text")),
        (("--model", "mock", "-M", "file=missing.jsonl"), ("missing.jsonl", "No such file")),
        (("--model", "orcale"), ("did you mean 'oracle'",)),
        (("--model", "opnai/some-model"), ("did you mean 'openai/some-model'",)),
        (("--model", "/no/such/model/folder"), ("/no/such/model/folder", "does not exist")),
        (("--model", "./no-such-folder"), ("does not exist",)),
    ],
)
def test_a_failed_start_leaves_nothing_and_the_corrected_command_runs(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    model: tuple[str, ...],
    needles: tuple[str, ...],
) -> None:
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "run"
    code, err = _main(capsys, *_run(out, model=model))
    _one_line_error(code, err, *needles)
    assert not out.exists()
    code, err = _main(capsys, *_run(out, model=("--model", "mock", "-M", "text=[]")))
    assert code == 0, err
    assert (out / "manifest.json").is_file() and (out / "records.jsonl").is_file()


@pytest.mark.skipif(find_spec("vllm") is not None, reason="vllm is installed here")
def test_a_missing_extra_is_reported_before_the_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    code, err = _main(capsys, *_run(out, model=("--model", "vllm/org/model")))
    _one_line_error(code, err, "pip install 'vlm-bench[vllm]'")
    assert not out.exists()


def test_a_model_that_fails_to_load_is_one_line_and_leaves_no_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import vlm_bench.runner.answers as answers_module
    import vlm_bench.runner.run_plan as plan_module

    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "config.json").write_text("{}")
    monkeypatch.setattr(plan_module, "check_backend", lambda *a, **k: _hf_check(folder))

    def broken_loader(model: str, args: object) -> Backend:
        raise OSError(f"Unable to load weights from {model}\nsecond line\nthird line")

    monkeypatch.setattr(answers_module, "resolve_backend", broken_loader)
    out = tmp_path / "run"
    code, err = _main(capsys, *_run(out, model=("--model", str(folder))))
    _one_line_error(code, err, "cannot load model", "OSError", "Unable to load weights")
    assert not out.exists()


def _hf_check(folder: Path) -> object:
    from vlm_bench.backends.preflight import BackendCheck

    return BackendCheck("hf", str(folder))


class _FailingBackend(Backend):
    name = "failing"

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        raise ConfigError("the server refuses this model")


def test_a_start_that_fails_after_the_folder_is_written_removes_it(tmp_path: Path) -> None:
    out = tmp_path / "results" / "run"
    options = {"tasks": (TASK,), "seeds": (0,), "images": False, "execute": False}
    with pytest.raises(ConfigError, match="refuses"):
        vlm_bench.run(model="oracle", out=out, backend=_FailingBackend(), **options)
    assert not out.exists()
    assert (tmp_path / "results").is_dir()  # only what the start created is removed
    result = vlm_bench.run(model="random", out=out, **options)
    assert len(result.records) == 2 and result.manifest.config.model == "random"


def test_a_resumed_run_that_fails_keeps_its_folder(tmp_path: Path) -> None:
    out = tmp_path / "run"
    options = {"tasks": (TASK,), "seeds": (0,), "images": False, "execute": False}
    vlm_bench.run(model="oracle", out=out, **options)
    for name in ("records.jsonl", "responses.jsonl"):  # nothing finished: the model is asked
        (out / name).write_text("")
    with pytest.raises(ConfigError, match="refuses"):
        vlm_bench.run(model="oracle", out=out, backend=_FailingBackend(), **options)
    assert (out / "manifest.json").is_file()


def test_an_unknown_hub_id_without_network_fails_fast(cli: Cli, tmp_path: Path) -> None:
    if find_spec("transformers") is None or find_spec("torch") is None:
        pytest.skip("needs the hf extra")
    env = {
        k: v for k, v in os.environ.items() if k not in ("HF_HUB_OFFLINE", "TRANSFORMERS_OFFLINE")
    }
    env["HF_HOME"] = str(tmp_path / "hf-home")  # an empty cache
    started = time.monotonic()
    done = cli.run(
        *_run(tmp_path / "run", model=("--model", "vlm-bench-tests/no-such-model")),
        env=env,
        timeout=90,
    )
    elapsed = time.monotonic() - started
    assert done.returncode == 2, done.stderr
    _one_line_error(done.returncode, done.stderr, "'vlm-bench-tests/no-such-model'")
    assert elapsed < 45, f"took {elapsed:.0f} s"
    assert not (tmp_path / "run").exists()


def test_an_uncached_hub_id_offline_is_refused_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    if find_spec("transformers") is None or find_spec("torch") is None:
        pytest.skip("needs the hf extra")
    monkeypatch.setenv("HF_HUB_OFFLINE", "1")
    out = tmp_path / "run"
    code, err = _main(capsys, *_run(out, model=("--model", "vlm-bench-tests/no-such-model")))
    _one_line_error(code, err, "not in the Hugging Face cache", "HF_HUB_OFFLINE")
    assert not out.exists()


# Files and folders --------------------------------------------------------------------------


def test_non_utf8_task_and_skill_files_are_named(tmp_path: Path) -> None:
    task_file = next((ROOT / "ground_truth" / "tasks").rglob("*.json"))
    skill_file = ROOT / "skills" / "pick.json"
    for source, model in ((task_file, TaskSpec), (skill_file, SkillSpec)):
        bad = tmp_path / source.name
        bad.write_bytes(source.read_bytes() + b"\xff\xfe")
        with pytest.raises(DataFileError, match=r"not UTF-8 text \(byte 0xff") as info:
            load_model(bad, model)
        assert str(bad) in str(info.value) and "\n" not in str(info.value)


def test_a_non_utf8_skill_file_through_the_cli(cli: Cli, tmp_path: Path) -> None:
    data = tmp_path / "data"
    for name in ("ground_truth", "skills", "prompts", "models"):
        if (ROOT / name).is_dir():
            shutil.copytree(ROOT / name, data / name)
    bad = data / "skills" / "pick.json"
    bad.write_bytes(bad.read_bytes() + b"\xff")
    done = cli.run("episode", TASK, env={**os.environ, "VLM_BENCH_DATA_DIR": str(data)})
    _one_line_error(done.returncode, done.stderr, str(bad), "not UTF-8")


def test_execute_checks_the_video_folder_before_simulating(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import vlm_bench.runner.task_execution as execution_module

    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("simulated before the video path was checked")

    monkeypatch.setattr(execution_module, "execute_task_plan", never)
    missing = tmp_path / "missing" / "v.gif"
    code, err = _main(capsys, "execute", TASK, "--video", str(missing))
    _one_line_error(code, err, "--video", str(missing.parent), "does not exist")
    code, err = _main(capsys, "execute", TASK, "--video", str(tmp_path))
    _one_line_error(code, err, "is a folder")


def test_output_paths_that_are_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    afile = tmp_path / "afile"
    afile.write_text("keep me")
    code, err = _main(capsys, *_run(afile))
    _one_line_error(code, err, str(afile), "is a file")
    code, err = _main(capsys, *_run(afile / "sub"))
    _one_line_error(code, err, str(afile), "is a file")
    for out in (afile, afile / "views"):
        code, err = _main(capsys, "render", TASK, "--out", str(out), "--size", "32")
        _one_line_error(code, err, "--out", "is a file")
    code, err = _main(capsys, "sheet", "--task", TASK, "--out", str(afile / "s.png"))
    _one_line_error(code, err, "--out", "is a file")
    assert afile.read_text() == "keep me"


@pytest.mark.parametrize(
    ("seeds", "needle"),
    [("0-99999999999", "99999999999"), ("0-20000", "too many seeds"), ("-3", "'-3'")],
)
def test_seed_ranges_are_capped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], seeds: str, needle: str
) -> None:
    out = tmp_path / "run"
    args = _run(out)
    args[args.index("--seeds") + 1] = seeds
    code, err = _main(capsys, *args)
    _one_line_error(code, err, needle)
    assert not out.exists()


# The simulator and the process --------------------------------------------------------------


def test_an_unstable_simulation_writes_no_log_file_into_the_working_folder(
    cli: Cli,
    tmp_path: Path,
) -> None:
    done = cli.run("execute", TASK, "--uav-noise", "1e300", "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["exec_success"] is False and "unstable" in result["failure_reason"]
    assert "Traceback" not in done.stderr
    assert list(tmp_path.iterdir()) == [], list(tmp_path.iterdir())


_TRITON_RUN = """
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import vlm_bench
from vlm_bench.backends import Backend, resolve_backend


class TritonBackend(Backend):
    # Loads triton's native library on first use, as transformers does through torch.
    name = "triton-user"

    def __init__(self):
        self.oracle = resolve_backend("oracle")

    def generate(self, requests, config):
        import triton._C.libtriton  # noqa: F401

        return self.oracle.generate(requests, config)


result = vlm_bench.run(
    model="triton-user", out=Path(sys.argv[1]), backend=TritonBackend(), tasks=("{task}",),
    seeds=(0,), resolution=32, execute=False, snapshot_cache=False,
)
print(len(result.records))
"""


_RENDER_FIRST = (
    "from vlm_bench.episodes import make_episode\n"
    "from vlm_bench.sim.render import SnapshotRenderer\n"
    "from vlm_bench.sim.scene import build_scene\n"
    f"scene = build_scene(make_episode('{TASK}', 0))\n"
    "SnapshotRenderer(shadows=False).render(scene.model, scene.data, 'overhead', 32)\n"
)


@pytest.mark.parametrize(
    "prelude",
    [
        pytest.param("", id="first-run"),
        # GL first (a renderer made outside any run, as a notebook or a gym environment does):
        # the renderer preloaded triton, and the run's own preload does not import it after EGL.
        pytest.param(_RENDER_FIRST, id="after-the-process-rendered"),
    ],
)
def test_a_run_whose_backend_loads_triton_after_rendering_does_not_crash(
    tmp_path: Path, prelude: str
) -> None:
    if find_spec("triton") is None:
        pytest.skip("triton is not installed")
    script = prelude + _TRITON_RUN.replace("{task}", TASK)
    done = subprocess.run(
        [sys.executable, "-c", script, str(tmp_path / "run")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=180,
        check=False,
    )
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    assert done.stdout.strip().splitlines()[-1] == "2"


@pytest.mark.slow
def test_a_first_hf_run_with_triton_installed_exits_0(cli: Cli, tmp_path: Path) -> None:
    if any(find_spec(m) is None for m in ("torch", "transformers", "tokenizers", "triton")):
        pytest.skip("needs torch, transformers, tokenizers and triton")
    build = (
        "import sys; sys.path.insert(0, sys.argv[2])\n"
        "from pathlib import Path\n"
        "from test_hf_backend import _build_tiny_llava\n"
        "_build_tiny_llava(Path(sys.argv[1]))\n"
    )
    model = tmp_path / "tiny-llava"
    subprocess.run(
        [sys.executable, "-c", build, str(model), str(ROOT / "tests" / "backends")],
        check=True,
        capture_output=True,
        timeout=300,
    )
    args = _run(tmp_path / "run", model=("--model", str(model)))
    args.remove("--no-images")
    done = cli.run(
        *args, "--resolution", "32", "--max-new-tokens", "4", "--no-snapshot-cache", cwd=tmp_path
    )
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])


# Every command ------------------------------------------------------------------------------


def _bad_values(tmp: Path) -> dict[str, list[list[str]]]:
    """Bad values for every command (keyed by command name)."""
    missing = str(tmp / "missing")
    return {
        "tasks": [["--suite", "nope"], ["--env", "nope"], ["--bogus"]],
        "episode": [["nope"], [TASK, "--seed", "x"], [TASK, "--seed", "99999999999"]],
        "render": [
            [TASK, "--out", str(tmp / "r"), "--size", "abc"],
            [TASK, "--out", missing, "--instruction", "nope"],
        ],
        "sheet": [
            ["--out", str(tmp / "s.png"), "--view", "nope"],
            ["--out", str(tmp / "s.png"), "--columns", "0"],
            ["--out", str(tmp / "s.png"), "--suite", "nope"],
            ["--out", str(tmp / "s.xyz")],
        ],
        "ground-truth": [["--write=maybe"]],
        "run": [
            ["--model", "oracle", "--views", "uav,top"],
            ["--model", "oracle", "--seeds", "x-1"],
            ["--model", "oracle", "--resolution", "0"],
            ["--model", "oracle", "--batch-size", "0"],
            ["--model", "oracle", "--instruction", "nope"],
            ["--model", ""],
            ["--model", "oracle", "-M", "novalue"],
        ],
        "rescore": [[missing], [str(tmp / "afile")]],
        "score": [
            [TASK, "--output", missing],
            ["nope", "--output", str(tmp / "afile")],
            [TASK, "--output", str(tmp / "afile"), "--instruction", "nope"],
        ],
        "execute": [
            ["nope"],
            [TASK, "--plan", missing],
            [TASK, "--seed", "-1"],
            [TASK, "--video", str(tmp / "v.mp3")],
            [TASK, "--variant", "nope"],
        ],
        "report": [[missing], [str(tmp / "afile")]],
        "models": [["nope"]],
        "prompt": [
            ["nope"],
            [TASK, "--seed", "x"],
            [TASK, "--views", "uav,top"],
            [TASK, "--instruction", "both"],
            [TASK, "--resolution", "0"],
            [TASK, "--k-shot", "-1"],
            [TASK, "--out", str(tmp / "afile")],
        ],
    }


def test_every_command_rejects_bad_values_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("not a run")
    _register()
    commands = {c.name or getattr(c.callback, "__name__", "") for c in app.registered_commands}
    cases = _bad_values(tmp_path)
    assert commands <= set(cases), f"add bad values for {sorted(commands - set(cases))}"
    for command in sorted(commands):
        for args in cases[command]:
            code, err = _main(capsys, command, *args)
            assert code != 0, (command, args)
            lines = err.strip().splitlines()
            assert len(lines) == 1 and "Traceback" not in err, (command, args, err)
            assert lines[0].startswith("error: "), (command, args, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]
