"""The SFT dataset's card (``README.md``): the YAML header ``datasets`` and the Hub read, then
what the rows are, what was left out, and the export's options."""

from __future__ import annotations

import json
from typing import Any

from vlm_bench.episodes.train_split import TOLERANCE, test_seeds_in
from vlm_bench.training.sft_export import SftCounts
from vlm_bench.types.run import RunConfig

SPLIT = "train"
"""The dataset's one split."""

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


def seed_split(config: RunConfig) -> str:
    """``train``, ``test`` or ``train+test``: which split the exported seeds belong to."""
    test = test_seeds_in(config.seeds)
    if not test:
        return "train"
    return "test" if len(test) == len(config.seeds) else "train+test"


def sft_card(config: RunConfig, counts: SftCounts, features: Any, arrow_bytes: int) -> str:
    """The card of an export of ``config`` that wrote ``counts``."""
    import yaml

    from vlm_bench import __version__
    from vlm_bench.types.benchmark_version import BENCHMARK_VERSION

    rows = sum(counts.rows.values())
    options = config.model_dump(mode="json", include=set(CARD_OPTIONS))
    header = {
        "license": "apache-2.0",
        "pretty_name": "vlm-bench planner SFT data",
        "task_categories": ["image-text-to-text"],
        "tags": ["robotics", "planning", "aerial-manipulation", "vlm-bench", "sft"],
        "configs": [
            {
                "config_name": "default",
                "data_files": [{"split": SPLIT, "path": f"data/{SPLIT}-*.parquet"}],
            }
        ],
        "dataset_info": {
            "config_name": "default",
            "features": features._to_yaml_list(),
            "splits": [{"name": SPLIT, "num_bytes": arrow_bytes, "num_examples": rows}],
            "dataset_size": arrow_bytes,
        },
        "vlm_bench": {
            "benchmark_version": BENCHMARK_VERSION,
            "package_version": __version__,
            "seeds": seed_split(config),
            "rows": rows,
            "options": options,
        },
    }
    test = test_seeds_in(config.seeds)
    leak = (
        f"**Contains test seeds {', '.join(map(str, test))}** (exported with "
        "`--allow-test-seeds`): a model trained on it must not be evaluated on them.\n\n"
        if test
        else ""
    )
    kinds = ", ".join(f"{n} {kind}" for kind, n in sorted(counts.rows.items())) or "none"
    ends = ", ".join(f"{n} {end}" for end, n in sorted(counts.ends.items())) or "no --perturb"
    repeats = ", ".join(counts.repeats) or "none"
    body = (
        "# vlm-bench planner SFT data\n\n"
        f"{leak}Written by `vlm-bench export sft` (vlm-bench {__version__}, benchmark version "
        f"{BENCHMARK_VERSION}). Rows are conversations in the form trl's `SFTTrainer` takes for "
        "vision-language models: `messages` (system, user and assistant turns whose content "
        'parts are `{"type": "text", "text": ...}` or `{"type": "image"}`) and `images` (one '
        "per image part, in order). The last assistant turn is the target: the GT plan "
        "(`kind` plan: round 0's prompt, exactly as `vlm-bench run` sends it) or the `rules` "
        "planner's recovery (`kind` replan: the replan a closed-loop run sends after a "
        "perturbed round failed, with the earlier rounds as turns).\n\n"
        f"- rows: {rows} ({kinds})\n"
        f"- scenes (task x seed): {counts.episodes}\n"
        f"- left out as repeats of a test episode (within {TOLERANCE}): {repeats}\n"
        f"- perturbed executions by end: {ends}\n\n"
        "## Options\n\n"
        f"```json\n{json.dumps(options, indent=1, sort_keys=True)}\n```\n"
    )
    head = yaml.safe_dump(header, sort_keys=False, allow_unicode=True, width=100)
    return f"---\n{head}---\n\n{body}"
