"""Model cards: valid data, recipes whose -M arguments each backend accepts, ``--model <card>``
resolution, ``vlm-bench models``, and a down server through the real console entry point."""

from __future__ import annotations

import json
import shlex
import subprocess
import sys
import types
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from vlm_bench.backends import (
    BACKENDS,
    parse_args,
    parse_model_args,
    resolve_backend,
    split_model,
)
from vlm_bench.backends.hf import HfArgs
from vlm_bench.backends.recipes import SERVER_URL, recipe_lines, run_line, serve_line
from vlm_bench.backends.vllm_backend import VllmArgs
from vlm_bench.catalog.files import load_model
from vlm_bench.catalog.model_cards import model_cards
from vlm_bench.errors import ConfigError, DataFileError
from vlm_bench.resources import models_dir
from vlm_bench.types.model_card import ModelCard

if TYPE_CHECKING:
    from tests.conftest import Cli

ROOT = Path(__file__).resolve().parents[2]
PAPER = {
    "Qwen3-VL-8B-Instruct",
    "Qwen2.5-VL-7B-Instruct",
    "GLM-4V-9B",
    "InternVL3.5-8B (HF format)",
    "LLaVA-OneVision-Qwen2-7B-OV",
    "Molmo-7B-D-0924",
}


def test_the_paper_models_have_cards() -> None:
    cards = model_cards()
    assert {c.title for c in cards.values() if c.in_paper} == PAPER
    assert cards["molmo-7b-d"].backend == "vllm" and "hf" in cards["molmo-7b-d"].unsupported
    assert "AutoModelForCausalLM" in cards["molmo-7b-d"].unsupported["hf"]
    assert cards["internvl3.5-8b"].hub_id.endswith("-HF")


@pytest.mark.parametrize("name", sorted(model_cards()))
def test_recipes_take_only_arguments_their_backend_accepts(name: str) -> None:
    card = model_cards()[name]
    if card.hf_args is not None:
        parse_args("hf", HfArgs, card.hf_args)
    if card.vllm_args is not None:
        parse_args("vllm", VllmArgs, card.vllm_args)
    for label, line in recipe_lines(card).items():
        words = shlex.split(line)
        if label == "server":
            assert words[:3] == ["vllm", "serve", card.hub_id]
            assert "--generation-config" in words  # no checkpoint sampling defaults
            continue
        backend = card.backend if label == "sampled" else label  # the authors' decoding
        model = words[words.index("--model") + 1]
        assert split_model(model) == (backend, card.hub_id)
        given = parse_model_args([words[i + 1] for i, w in enumerate(words) if w == "-M"])
        expected = {"base_url": SERVER_URL} if label == "openai" else card.args_for(backend)
        assert given == expected


def test_unsupported_backends_have_no_recipe() -> None:
    molmo = model_cards()["molmo-7b-d"]
    assert set(recipe_lines(molmo)) == {"vllm", "server", "openai"}
    with pytest.raises(ConfigError, match="does not run on hf: remote code only"):
        run_line(molmo, "hf")
    glm = model_cards()["glm-4v-9b"]
    assert "--views uav" in run_line(glm, "vllm") and "'{\"image\": 1}'" in serve_line(glm)


def test_a_card_file_is_validated(tmp_path: Path) -> None:
    data: dict[str, Any] = json.loads((models_dir() / "qwen2.5-vl-7b.json").read_text())
    data["unsupported"] = {"hf": "because"}  # but hf_args are given
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(DataFileError, match=r"bad\.json.*hf_args must be given exactly when"):
        load_model(bad, ModelCard)


def test_a_card_name_selects_its_backend_checkpoint_and_arguments(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    assert split_model("qwen2.5-vl-7b") == ("hf", "Qwen/Qwen2.5-VL-7B-Instruct")
    assert split_model("vllm/qwen2.5-vl-7b") == ("vllm", "Qwen/Qwen2.5-VL-7B-Instruct")
    assert split_model("openai/molmo-7b-d") == ("openai", "allenai/Molmo-7B-D-0924")
    assert split_model("./qwen2.5-vl-7b") == ("hf", "./qwen2.5-vl-7b")  # a folder
    engines: list[dict[str, Any]] = []
    fake = types.ModuleType("vllm")
    fake.LLM = lambda **kwargs: engines.append(kwargs)  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "vllm", fake)
    resolve_backend("molmo-7b-d", {"max_model_len": "2048"})
    [engine] = engines
    assert engine["model"] == "allenai/Molmo-7B-D-0924"
    assert engine["trust_remote_code"] is True and engine["max_model_len"] == 2048  # -M wins


def test_an_unknown_bare_model_name_is_one_line_with_a_suggestion() -> None:
    with pytest.raises(ConfigError, match=r"unknown model 'orcale'.*did you mean 'oracle'") as info:
        split_model("orcale")
    assert "qwen2.5-vl-7b" in str(info.value) and "\n" not in str(info.value)


def test_models_command_lists_backends_and_cards_without_torch() -> None:
    code = (
        "import sys; from vlm_bench.cli.main import main; sys.argv = ['vlm-bench', 'models'];"
        "\ntry: main()\nexcept SystemExit: pass\n"
        "print('HEAVY', [m for m in ('torch', 'transformers', 'vllm', 'openai') "
        "if m in sys.modules])"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
        check=True,
        env={"COLUMNS": "200", "PATH": "/usr/bin:/bin"},
    ).stdout
    for name in [*BACKENDS.names(), *model_cards()]:
        assert name in out
    assert "HEAVY []" in out


def test_models_command_prints_a_cards_recipe(cli: Cli) -> None:
    shown = cli.run("models", "qwen2.5-vl-7b")
    assert shown.returncode == 0, shown.stderr
    flat = " ".join(shown.stdout.split())
    card = model_cards()["qwen2.5-vl-7b"]
    for line in recipe_lines(card).values():
        assert line in flat
    as_json = json.loads(cli.run("models", "qwen2.5-vl-7b", "--json").stdout)
    assert as_json["hub_id"] == card.hub_id and set(as_json["commands"]) == set(recipe_lines(card))
    missing = cli.run("models", "qwen9")
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1
    assert "unknown model card 'qwen9'" in missing.stderr


def test_a_run_against_a_down_server_stops_with_the_cause(tmp_path: Path, cli: Cli) -> None:
    import socket

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        url = f"http://127.0.0.1:{sock.getsockname()[1]}/v1"
    done = cli.run(
        "run",
        "--model",
        "openai/m",
        "-M",
        f"base_url={url}",
        "--task",
        "standard_pick_place",
        "--no-images",
        "--no-execute",
        "--no-progress",
        "--out",
        str(tmp_path / "run"),
    )
    assert done.returncode != 0
    assert f"cannot reach the OpenAI-compatible server at {url}" in done.stderr
    assert "Traceback" not in done.stderr and done.stderr.count("\n") == 1
    assert (
        not (tmp_path / "run" / "records.jsonl").exists()
        or not (tmp_path / "run" / "records.jsonl").read_text()
    )
