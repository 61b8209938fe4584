"""The SFT export as a dataset folder: its features, its card and the streamed write
(docs/training.md#sft-export-schema)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vlm_bench.episodes.train_split import TOLERANCE, test_seeds_in
from vlm_bench.runner.progress import progress_bar
from vlm_bench.training.parquet_rows import SHARD_GLOB, ShardWriter, require_datasets
from vlm_bench.training.sft_export import SftCounts, check_out_folder, scene_count, sft_examples
from vlm_bench.training.sft_rows import SftExample
from vlm_bench.types.run import RunConfig

CARD = "README.md"
CARD_OPTIONS = (
    "tasks",
    "suite",
    "seeds",
    "instructions",
    "views",
    "resolution",
    "labels",
    "k_shot",
    "few_shot_seed",
    "object_list",
    "images",
    "scene_as_text",
    "perturb",
    "max_rounds",
    "step_budget",
    "history",
    "uav_noise",
)
"""The export's options the card records (selection, prompt, perturbations)."""


def sft_features() -> Any:
    """The export's ``datasets.Features`` (one column per :class:`SftExample` field)."""
    ds = require_datasets()
    part = {"type": ds.Value("string"), "text": ds.Value("string")}
    message = {"role": ds.Value("string"), "content": ds.List(part)}
    return ds.Features(
        {
            "key": ds.Value("string"),
            "task_id": ds.Value("string"),
            "suite": ds.Value("string"),
            "seed": ds.Value("int64"),
            "instruction": ds.Value("string"),
            "round": ds.Value("int32"),
            "kind": ds.Value("string"),
            "messages": ds.List(message),
            "images": ds.List(ds.Image()),
            "target": ds.Value("string"),
            "prompt_hash": ds.Value("string"),
        }
    )


def _row(example: SftExample) -> dict[str, Any]:
    row = example.model_dump(exclude={"images"})
    row["messages"] = list(example.messages)
    row["images"] = [{"bytes": png, "path": None} for png in example.images]
    return row


@dataclass(frozen=True)
class SftExport:
    """What :func:`export_sft` wrote."""

    folder: Path
    rows: int
    counts: SftCounts
    shards: tuple[Path, ...]


def export_sft(
    config: RunConfig,
    out: Path,
    *,
    force: bool = False,
    allow_test_seeds: bool = False,
    progress: bool = False,
) -> SftExport:
    """Write the SFT dataset of ``config``'s selection and prompt options into ``out``.

    Args:
        config: Selection (tasks or suite, seeds, instructions), prompt options, and
            ``perturb`` (with ``loop``, ``max_rounds``) for replan rows.
        out: The dataset folder (empty, or ``force``).
        force: Write into a non-empty folder (its shards and card are replaced).
        allow_test_seeds: Accept seeds 0-9 (the card says so).
        progress: A progress bar on stderr.

    Raises:
        ConfigError: Test seeds without ``allow_test_seeds``, a non-empty ``out``.
        MissingExtraError: ``datasets`` is missing.
    """
    features = sft_features()
    check_out_folder(out, force)
    counts = SftCounts()
    rows = sft_examples(config, counts, allow_test_seeds=allow_test_seeds)  # checks seeds first
    first = next(rows, None)
    if force:
        for old in out.glob(SHARD_GLOB):
            old.unlink()
    writer = ShardWriter(out, features)
    with progress_bar(scene_count(config), "sft export", enabled=progress) as advance:
        for done, examples in [first] if first is not None else []:
            writer.write([_row(e) for e in examples])
            advance(done)
        for done, examples in rows:
            writer.write([_row(e) for e in examples])
            advance(done)
    shards = writer.close()
    (out / CARD).write_text(sft_card(config, counts, writer.rows, allow_test_seeds, features))
    return SftExport(out, writer.rows, counts, tuple(shards))


def sft_card(
    config: RunConfig, counts: SftCounts, rows: int, allow_test_seeds: bool, features: Any
) -> str:
    """The dataset card: the YAML header ``datasets`` reads, then what the rows are."""
    from vlm_bench import __version__
    from vlm_bench.types.benchmark_version import BENCHMARK_VERSION

    info = {"features": features._to_yaml_list()}
    header = {
        "configs": [
            {"config_name": "default", "data_files": [{"split": "train", "path": SHARD_GLOB}]}
        ],
        "dataset_info": info,
        "license": "apache-2.0",
        "tags": ["vlm-bench", "sft", "robotics", "planning"],
        "vlm_bench": {"benchmark_version": BENCHMARK_VERSION, "split": _split(config)},
    }
    test = test_seeds_in(config.seeds)
    leak = (
        f"**Contains test seeds {', '.join(map(str, test))}** (exported with "
        "`--allow-test-seeds`): do not evaluate a model trained on it on those seeds.\n\n"
        if allow_test_seeds and test
        else ""
    )
    options = config.model_dump(mode="json", include=set(CARD_OPTIONS))
    ends = ", ".join(f"{k} {v}" for k, v in sorted(counts.ends.items())) or "(no --perturb)"
    return "\n".join(
        [
            "---",
            _yaml(header).rstrip(),
            "---",
            "",
            "# vlm-bench planner SFT data",
            "",
            leak
            + f"Generated by vlm-bench {__version__} (benchmark version {BENCHMARK_VERSION}) with "
            "`vlm-bench export sft`. Conversational rows in the form trl's `SFTTrainer` takes "
            "for vision-language models: `messages` (system, user, assistant turns; image "
            'parts are `{"type": "image"}` placeholders) and `images` (one per image '
            "part, in order). The last assistant turn is the target: the GT plan (`kind` plan) "
            "or the `rules` planner's recovery after a perturbed execution failed (`kind` "
            "replan).",
            "",
            f"- rows: {rows} ({', '.join(f'{k} {v}' for k, v in sorted(counts.rows.items()))})",
            f"- scenes (task x seed): {counts.episodes}",
            f"- left out as repeats of a test episode (tolerance {TOLERANCE}): "
            f"{len(counts.repeats)} {counts.repeats[:20]}",
            f"- perturbed executions: {ends}",
            "",
            "Options:",
            "",
            "```json",
            json.dumps(options, indent=1, sort_keys=True),
            "```",
            "",
        ]
    )


def _split(config: RunConfig) -> str:
    test = test_seeds_in(config.seeds)
    if not test:
        return "train"
    return "test" if len(test) == len(config.seeds) else "train+test"


def _yaml(data: Any) -> str:
    import yaml

    return str(yaml.safe_dump(data, sort_keys=False, allow_unicode=True))
