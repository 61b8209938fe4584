"""Model-string rules, -M argument parsing, entry-point plug-ins, lazy heavy imports."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Mapping, Sequence

import pytest

import vlm_bench.backends.backend_registry as registry_module
from vlm_bench.backends import (
    BACKENDS,
    Backend,
    BackendArgs,
    parse_model_args,
    resolve_backend,
    split_model,
)
from vlm_bench.backends.builtin import MockBackend, OracleBackend, RandomBackend
from vlm_bench.backends.preflight import check_backend
from vlm_bench.errors import ConfigError, DuplicateNameError, MissingExtraError
from vlm_bench.registry import Registry
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult


@pytest.mark.parametrize(
    ("model", "expected"),
    [
        ("oracle", ("oracle", "")),
        ("random", ("random", "")),
        ("mock", ("mock", "")),
        ("openai/gpt-4o-mini", ("openai", "gpt-4o-mini")),
        ("openai/Qwen/Qwen2.5-VL-7B-Instruct", ("openai", "Qwen/Qwen2.5-VL-7B-Instruct")),
        ("vllm/Qwen/Qwen3-VL-8B-Instruct", ("vllm", "Qwen/Qwen3-VL-8B-Instruct")),
        ("Qwen/Qwen2.5-VL-7B-Instruct", ("hf", "Qwen/Qwen2.5-VL-7B-Instruct")),
        ("/models/llava", ("hf", "/models/llava")),
        ("./vllm/local-copy", ("hf", "./vllm/local-copy")),
        ("random/some-model", ("hf", "random/some-model")),  # built-ins take no model
        ("hf/model", ("hf", "hf/model")),  # "hf/" is an ordinary org name
    ],
)
def test_model_string_rules(model: str, expected: tuple[str, str]) -> None:
    assert split_model(model) == expected


def test_resolve_builds_the_builtins() -> None:
    assert isinstance(resolve_backend("oracle"), OracleBackend)
    assert isinstance(resolve_backend("random", {"seed": "9"}), RandomBackend)
    assert isinstance(resolve_backend("mock", {"text": "x"}), MockBackend)
    with pytest.raises(ConfigError, match="empty model string"):
        split_model("")


def test_arg_typos_list_the_valid_keys() -> None:
    with pytest.raises(ConfigError) as info:
        resolve_backend("random", {"sede": "1"})
    message = str(info.value)
    assert "'sede'" in message and "max_steps, min_steps, seed" in message
    assert "\n" not in message
    with pytest.raises(ConfigError, match=r"seed='abc'.*valid integer.*valid keys"):
        resolve_backend("random", {"seed": "abc"})


def test_parse_model_args() -> None:
    assert parse_model_args(["a=1", "b=x=y", "a=2", "c="]) == {"a": "2", "b": "x=y", "c": ""}
    with pytest.raises(ConfigError, match="key=value"):
        parse_model_args(["novalue"])


class _EchoBackend(Backend):
    name = "echo"

    def __init__(self, model: str, args: BackendArgs) -> None:
        self.model = model

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        return [GenerationResult(id=r.id, text=self.model) for r in requests]


class _FakeEntryPoint:
    def __init__(self, name: str, target: object) -> None:
        self.name, self.value, self._target = name, f"fake:{name}", target

    def load(self) -> object:
        return self._target


def _fresh_registry(monkeypatch: pytest.MonkeyPatch, eps: list[_FakeEntryPoint]) -> None:
    fresh: Registry[registry_module.BackendEntry] = Registry("backend")
    for name in BACKENDS.names():
        fresh.add(name, BACKENDS.get(name))
    monkeypatch.setattr(registry_module, "BACKENDS", fresh)
    monkeypatch.setattr(registry_module, "_plugins_loaded", False)
    monkeypatch.setattr(registry_module, "entry_points", lambda group: eps)


def test_entry_point_backends_are_selected_by_prefix(monkeypatch: pytest.MonkeyPatch) -> None:
    def factory(model: str, args: Mapping[str, str]) -> Backend:
        return _EchoBackend(model + args.get("suffix", ""), BackendArgs())

    _fresh_registry(
        monkeypatch, [_FakeEntryPoint("echo", _EchoBackend), _FakeEntryPoint("fn", factory)]
    )
    echo = resolve_backend("echo/my-model")
    assert isinstance(echo, _EchoBackend) and echo.model == "my-model"
    fn = resolve_backend("fn/x", {"suffix": "!"})
    assert isinstance(fn, _EchoBackend) and fn.model == "x!"
    with pytest.raises(ConfigError, match="unknown -M argument 'oops'"):
        resolve_backend("echo/m", {"oops": "1"})


def test_a_plugin_backends_arguments_are_checked_before_the_run_starts(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """check_backend (what a run calls before writing anything) validates a plug-in class's
    -M arguments against its Args without building it; a factory's are checked when built."""
    built: list[str] = []

    def factory(model: str, args: Mapping[str, str]) -> Backend:
        built.append(model)
        return _EchoBackend(model, BackendArgs())

    _fresh_registry(
        monkeypatch,
        [
            _FakeEntryPoint("echo", _EchoBackend),
            _FakeEntryPoint("fn", factory),
            _FakeEntryPoint("junk", 42),
        ],
    )
    with pytest.raises(ConfigError, match="unknown -M argument 'oops'"):
        check_backend("echo/m", {"oops": "1"})
    assert check_backend("echo/m").name == "echo"
    assert check_backend("fn/m", {"anything": "1"}).name == "fn" and built == []
    with pytest.raises(ConfigError, match="must be a Backend subclass"):
        check_backend("junk/m")


def test_duplicate_entry_point_names_are_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    _fresh_registry(monkeypatch, [_FakeEntryPoint("openai", _EchoBackend)])
    with pytest.raises(DuplicateNameError, match="'openai'"):
        split_model("anything")


def test_bad_entry_point_target(monkeypatch: pytest.MonkeyPatch) -> None:
    _fresh_registry(monkeypatch, [_FakeEntryPoint("junk", 42)])
    with pytest.raises(ConfigError, match="must be a Backend subclass"):
        resolve_backend("junk/m")


def test_missing_extras_are_actionable(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "vllm", None)  # import vllm -> ImportError
    with pytest.raises(MissingExtraError, match=r"pip install 'vlm-bench\[vllm\]'"):
        resolve_backend("vllm/some/model")
    monkeypatch.setitem(sys.modules, "openai", None)
    with pytest.raises(MissingExtraError, match=r"vlm-bench\[openai\]"):
        resolve_backend("openai/m")
    monkeypatch.setitem(sys.modules, "transformers", None)
    with pytest.raises(MissingExtraError, match=r"vlm-bench\[hf\]"):
        resolve_backend("org/model")


def test_importing_backends_imports_no_heavy_dependency() -> None:
    code = (
        "import sys, vlm_bench.backends as b, vlm_bench.prompting;"
        "b.split_model('openai/x'); b.resolve_backend('oracle');"
        "heavy = [m for m in ('torch', 'transformers', 'openai', 'vllm', 'xgrammar') "
        "if m in sys.modules];"
        "print(','.join(heavy))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert out.stdout.strip() == ""
