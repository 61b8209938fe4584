"""The SFT loop closes: trl's own ``SFTTrainer`` trains a tiny vision-language model (LLaVA built
from a config, with a BPE tokenizer trained on the export's text: no hub) a few steps on an SFT
export read back from disk, saves a checkpoint, and ``vlm-bench run --model <checkpoint>``
plans with it."""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

pytest.importorskip("torch")
pytest.importorskip("transformers")
pytest.importorskip(
    "trl", reason="trl is not installed: pip install 'vlm-bench[train]' (it is in [dev] too)"
)
datasets = pytest.importorskip("datasets")

from vlm_bench.training import export_sft  # noqa: E402
from vlm_bench.types.run import RunConfig  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
TASK = "standard_pick_place"


def _tiny_vlms() -> ModuleType:
    spec = importlib.util.spec_from_file_location("tiny_vlms", ROOT / "benchmarks/tiny_vlms.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["tiny_vlms"] = module
    spec.loader.exec_module(module)
    return module


def _load(folder: Path, cache: Path) -> Any:
    """The export as ``datasets`` loads it (a cache of its own: tests reuse folder names)."""
    return datasets.load_dataset(str(folder), split="train", cache_dir=str(cache))


def _texts(rows: Any) -> list[str]:
    return [p["text"] for row in rows for m in row["messages"] for p in m["content"] if p["text"]]


@pytest.fixture(scope="module")
def export(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Plan rows of a train seed, both instructions, four views at 32 px, no few-shot."""
    out = tmp_path_factory.mktemp("sft") / "data"
    config = RunConfig(model="sft", tasks=(TASK,), seeds=(12,), resolution=32, k_shot=0)
    export_sft(config, out)
    return out


def test_sft_trainer_trains_a_tiny_vlm_whose_checkpoint_vlm_bench_runs(
    export: Path, tmp_path: Path
) -> None:
    import torch
    from trl import SFTConfig, SFTTrainer

    rows = _load(export, tmp_path / "cache")
    assert len(rows) == 2
    tiny = _tiny_vlms()
    built = tiny._llava(_texts(rows) * 2)
    start = built.save(tmp_path / "tiny")
    before = {k: v.clone() for k, v in built.model.state_dict().items()}

    args = SFTConfig(
        output_dir=str(tmp_path / "trainer"),
        max_steps=3,
        per_device_train_batch_size=2,
        learning_rate=1e-3,
        max_length=None,  # never cut a prompt: the target is at its end
        logging_steps=1,
        save_strategy="no",
        report_to="none",
        use_cpu=True,
        dataloader_num_workers=0,
        seed=0,
    )
    trainer = SFTTrainer(model=str(start), args=args, train_dataset=rows)
    trainer.train()
    losses = [log["loss"] for log in trainer.state.log_history if "loss" in log]
    assert len(losses) == 3 and all(math.isfinite(x) for x in losses)
    checkpoint = tmp_path / "checkpoint"
    trainer.save_model(str(checkpoint))
    after = trainer.model.state_dict()
    assert any(not torch.equal(before[k], after[k].cpu()) for k in before if k in after)

    out = tmp_path / "run"
    tiny.cli_run(out, checkpoint, 2, "--resolution", "32", "--seeds", "0")
    records = [json.loads(line) for line in (out / "records.jsonl").open()]
    assert len(records) == 2
    assert all(r["status"] != "error" and r.get("backend_error") is None for r in records)


@pytest.mark.smoke  # the trl SFT loop in the default suite
def test_prompt_completion_form_trains_on_the_answer_only(export: Path, tmp_path: Path) -> None:
    """The recipe's variant: ``messages`` split into ``prompt`` and ``completion`` (trl then
    computes the loss on the completion alone)."""
    from trl import SFTConfig, SFTTrainer

    rows = _load(export, tmp_path / "cache")
    pairs = rows.map(
        lambda r: {"prompt": r["messages"][:-1], "completion": r["messages"][-1:]},
        remove_columns=["messages"],
    )
    built = _tiny_vlms()._llava(_texts(rows) * 2)
    start = built.save(tmp_path / "tiny")
    args = SFTConfig(
        output_dir=str(tmp_path / "trainer"),
        max_steps=1,
        per_device_train_batch_size=2,
        max_length=None,
        save_strategy="no",
        report_to="none",
        use_cpu=True,
        dataloader_num_workers=0,
    )
    trainer = SFTTrainer(model=str(start), args=args, train_dataset=pairs)
    batch = trainer.data_collator([pairs[0], pairs[1]])
    answer_tokens = int((batch["labels"] != -100).sum())
    target = built.tokenizer(pairs[0]["completion"][0]["content"][0]["text"])["input_ids"]
    assert 0 < answer_tokens < 3 * len(target)  # the answers, not the long prompts
    trainer.train()
    assert math.isfinite(trainer.state.log_history[-1]["train_loss"])


@pytest.mark.slow
def test_the_recipes_trl_sft_command_reads_the_export(export: Path, tmp_path: Path) -> None:
    """docs/training.md's ``trl sft`` command (its data options; a tiny model, 2 steps on CPU)
    loads the export folder as is and saves a checkpoint ``vlm-bench run`` plans with."""
    import subprocess

    tiny = _tiny_vlms()
    rows = _load(export, tmp_path / "cache")
    start = tiny._llava(_texts(rows) * 2).save(tmp_path / "tiny")
    checkpoint = tmp_path / "checkpoint"
    command = [sys.executable, "-c", "import sys; from trl.cli import main; sys.exit(main())"]
    command += ["sft", "--model_name_or_path", str(start), "--dataset_name", str(export)]
    command += ["--output_dir", str(checkpoint), "--max_length", "16384", "--max_steps", "2"]
    command += ["--per_device_train_batch_size", "1", "--gradient_accumulation_steps", "2"]
    command += ["--learning_rate", "1e-3", "--use_cpu", "--report_to", "none"]
    command += ["--save_strategy", "no", "--dataloader_num_workers", "0"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    out = tmp_path / "run"
    tiny.cli_run(out, checkpoint, 2, "--resolution", "32", "--seeds", "0")
    assert len((out / "records.jsonl").read_text().splitlines()) == 2
