"""The lmms-eval tasks shipped in the package: their YAML loads as lmms-eval loads it (``include``,
``!function utils.name`` from the YAML's folder), and their hooks give the scorer's numbers."""

from __future__ import annotations

import json
from pathlib import Path
from types import ModuleType
from typing import Any

import datasets
import pytest
import yaml

import vlm_bench
from tests.conftest import module_from_file
from vlm_bench.export.dataset_export import DatasetExport
from vlm_bench.lmms import TASKS_DIR
from vlm_bench.types.task import Suite

FOLDER = TASKS_DIR / "vlm_bench_aerial"
METRICS = ("s_plan", "s_loc", "s_obj", "s_skill", "s_total", "succ")


def _utils() -> ModuleType:
    """``utils.py`` loaded from its file, as lmms-eval loads a task's functions."""
    return module_from_file("utils", FOLDER / "utils.py")


def _load(path: Path) -> dict[str, Any]:
    """A task YAML with its ``include`` merged and ``!function`` tags resolved (lmms-eval's
    rules: the included file is read first, the including file's keys win)."""
    utils = _utils()

    class Loader(yaml.SafeLoader):
        pass

    def function(loader: yaml.SafeLoader, node: yaml.Node) -> Any:
        module, name = str(loader.construct_scalar(node)).split(".")  # type: ignore[arg-type]
        assert module == "utils"
        return getattr(utils, name)

    Loader.add_constructor("!function", function)
    config: dict[str, Any] = yaml.load(path.read_text(), Loader=Loader)
    include = config.pop("include", None)
    if include is None:
        return config
    return {**_load(path.parent / include), **config}


@pytest.mark.parametrize(
    ("name", "dataset_path"),
    [("vlm_bench_aerial", "vlm-bench-aerial"), ("vlm_bench_aerial_text", "vlm-bench-aerial-text")],
)
def test_the_task_yaml_loads(name: str, dataset_path: str) -> None:
    config = _load(FOLDER / f"{name}.yaml")
    assert config["task"] == name and config["dataset_path"] == dataset_path
    assert config["test_split"] == "test" and config["output_type"] == "generate_until"
    for hook in ("doc_to_visual", "doc_to_text", "doc_to_messages", "process_results"):
        assert callable(config[hook]), hook
    names = [m["metric"] for m in config["metric_list"]]
    assert names == [*METRICS, *(f"{m}_{s.value}" for s in Suite for m in METRICS)]
    assert all(m["aggregation"] == "mean" and m["higher_is_better"] for m in config["metric_list"])
    assert config["generation_kwargs"]["temperature"] == 0


def test_lmms_eval_indexes_only_the_two_tasks() -> None:
    assert sorted(p.name for p in FOLDER.glob("*.yaml")) == [
        "vlm_bench_aerial.yaml",
        "vlm_bench_aerial_text.yaml",
    ]


def test_the_hooks_give_the_prompt_and_the_scores(small: DatasetExport) -> None:
    utils = _utils()
    docs = datasets.load_dataset(str(small.folder), split="test")
    for doc in docs:
        system, user = utils.vlm_bench_doc_to_messages(doc)
        assert system == {"role": "system", "content": [{"type": "text", "text": doc["system"]}]}
        assert user["role"] == "user"
        shown = "\n".join(
            c["text"] if c["type"] == "text" else f"<image:{_view_of(doc, c['url'])}>"
            for c in user["content"]
        )
        assert shown == doc["user"]
        visuals = utils.vlm_bench_doc_to_visual(doc)
        assert [v.tobytes() for v in visuals] == [
            doc[f"image_{view}"].convert("RGB").tobytes() for view in doc["views"]
        ]
        assert utils.vlm_bench_doc_to_text(doc).endswith(doc["user"])

        answer = doc["gt_plan"] if doc["seed"] == 0 and doc["instruction"] == "explicit" else "[]"
        metrics = utils.vlm_bench_process_results(doc, [answer])
        scores = vlm_bench.score_answer(doc["key"], answer).scores
        expected = {
            "s_plan": scores.s_plan,
            "s_loc": scores.s_loc,
            "s_obj": scores.s_obj,
            "s_skill": scores.s_skill,
            "s_total": scores.s_total,
            "succ": 100.0 if scores.succ else 0.0,
        }
        suite = doc["suite"]
        assert metrics == {**expected, **{f"{k}_{suite}": v for k, v in expected.items()}}
    assert json.loads(docs[0]["gt_plan"])  # the GT answer above scored, not an empty plan


def _view_of(doc: dict[str, Any], image: Any) -> str:
    """The view whose image ``image`` is (same pixels)."""
    pixels = image.tobytes()
    (view,) = [v for v in doc["views"] if doc[f"image_{v}"].convert("RGB").tobytes() == pixels]
    return str(view)
