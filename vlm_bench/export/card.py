"""The dataset card (``README.md``): the YAML header ``datasets`` and the Hub read (configs,
splits, features, license) with the benchmark version and the export's options, then a short
description of the columns and how to score an answer."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

from vlm_bench.export.options import ExportOptions
from vlm_bench.export.row_model import DatasetRow, image_column

if TYPE_CHECKING:
    import datasets

SPLIT = "test"
"""The dataset's one split: the benchmark is for evaluation only."""

LICENSE = "apache-2.0"
"""The package's license, which covers the generated episodes and renders."""

CARD_KEY = "vlm_bench"
"""The card's header section holding the benchmark version and export options."""


def card_metadata(
    options: ExportOptions,
    features: datasets.Features,
    rows: int,
    arrow_bytes: int,
    package_version: str,
) -> dict[str, Any]:
    """The card's YAML header as data (``arrow_bytes``: the rows' size in memory, which
    ``datasets`` calls a split's ``num_bytes``)."""
    from vlm_bench.types.benchmark_version import BENCHMARK_VERSION

    return {
        "license": LICENSE,
        "pretty_name": "vlm-bench aerial manipulation planning",
        "task_categories": ["image-text-to-text"],
        "tags": ["robotics", "planning", "aerial-manipulation", "vlm-bench"],
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
        CARD_KEY: {
            "benchmark_version": BENCHMARK_VERSION,
            "package_version": package_version,
            "rows": rows,
            "options": options.model_dump(mode="json"),
        },
    }


def _yaml(data: dict[str, Any]) -> str:
    import yaml

    return str(yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=100))


def _options_table(options: ExportOptions) -> str:
    lines = ["| option | value |", "|---|---|"]
    for name, value in options.model_dump(mode="json").items():
        shown = ", ".join(map(str, value)) if isinstance(value, list) else json.dumps(value)
        lines.append(f"| `{name}` | {shown or '(all)'} |")
    return "\n".join(lines)


def card_text(
    options: ExportOptions,
    features: datasets.Features,
    rows: int,
    arrow_bytes: int,
    package_version: str,
    example: DatasetRow | None = None,
) -> str:
    """The whole ``README.md``: YAML header, then the description."""
    from vlm_bench.types.benchmark_version import BENCHMARK_VERSION

    header = _yaml(card_metadata(options, features, rows, arrow_bytes, package_version))
    images = ", ".join(f"`{image_column(v)}`" for v in options.views)
    key = example.key if example is not None else "drawer_interaction/0/explicit"
    body = f"""# vlm-bench aerial manipulation planning (benchmark version {BENCHMARK_VERSION})

Vision-language models as task planners for an aerial manipulator (a quadrotor carrying a
Franka Panda arm), on the metrics of the AIR-VLA paper. One row per episode (task × seed ×
instruction variant): {rows} rows in the `{SPLIT}` split, exported by vlm-bench
{package_version}.

Each row holds exactly what `vlm-bench run` with these options sends a model: the `system`
text, the `user` text with `<image:view>` on its own line where each image goes, and the
images ({images}: PNG at {options.resolution} px, in the order of `views`). A model answers
with a JSON plan; score the answer with the package (no simulator needed):

```python
import datasets, vlm_bench
ds = datasets.load_dataset("path/to/this/folder", split="{SPLIT}")
row = ds[0]
scores = vlm_bench.score_answer(row, answer_text).scores
scores.s_plan, scores.s_loc, scores.s_obj, scores.s_skill, scores.s_total, scores.succ
vlm_bench.score_answer("{key}", answer_text)  # or by episode key
```

A row of another benchmark version is refused: scores of different versions are not
comparable.

## Columns

- `key`: episode key `task_id/seed/variant`; `task_id`, `suite`, `seed`, `instruction`
  (`explicit` or `implicit`), `instruction_text`; `benchmark_version`.
- `system`, `user`: the prompt; `views`: the images' views in prompt order; {images}: the images.
- `objects`: the object and part ids a plan may name; `gt_plan`: the GT plan as JSON in the
  paper's format; `gt_steps`: the same as structured steps.
- `prompt_hash`: the hash a run's record of the episode stores; `example_ids`: the few-shot
  examples in the system text.

## Options of this export

{_options_table(options)}
"""
    return f"---\n{header}---\n\n{body}"


def read_card_options(text: str) -> dict[str, Any]:
    """The ``vlm_bench`` section of a card's YAML header (empty when there is none)."""
    import yaml

    if not text.startswith("---\n"):
        return {}
    end = text.find("\n---\n", 4)
    if end < 0:
        return {}
    data = yaml.safe_load(text[4:end])
    section = data.get(CARD_KEY) if isinstance(data, dict) else None
    return section if isinstance(section, dict) else {}
