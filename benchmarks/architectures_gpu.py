"""Run every tiny architecture (benchmarks/tiny_vlms.py) through ``vlm-bench run --model
<folder>`` in bf16 on the GPU: 8 episodes at batch 1 and at batch 8, the real 448 px views
(after a warm-up run that renders them).

For each architecture it reports whether the folder was built and loaded, the image tokens of
each of the four views (and that each sits after its label), whether greedy batch 8 equals
batch 1, and the wall time of each run. Needs torch with CUDA, transformers and torchvision
(the five processors with a video processor); without CUDA it runs in float32 on the CPU, and
without torchvision it runs what it can and says what it skipped.

    MUJOCO_GL=egl python benchmarks/architectures_gpu.py [--out results.json] [--only NAME]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import tiny_vlms

from vlm_bench.episodes import make_episode
from vlm_bench.prompting import build_prompt
from vlm_bench.types.run import RunConfig


def _corpus() -> list[str]:
    episode = make_episode("standard_pick_place", 0)
    prompt_config = RunConfig(model="mock", images=False, k_shot=0).prompt_config("explicit")
    system = build_prompt(episode, {}, prompt_config).to_request("x").system
    plan = '[{"subtask": 0, "tasktype": "UAV", "direction": "frontleft"}]'
    return [system, *tiny_vlms.VIEWS.values(), plan] * 3


def _device() -> tuple[str, str]:
    import torch

    if torch.cuda.is_available():
        return torch.cuda.get_device_name(0), "bfloat16"
    return "CPU (no CUDA)", "float32"


def run_arch(arch: Any, corpus: list[str], dtype: str, work: Path) -> dict[str, Any]:
    """Build, save and run one architecture; what happened, as a dict."""
    row: dict[str, Any] = {"arch": arch.name, "card": arch.card, "dtype": dtype}
    built = arch.build(corpus)
    row["built"] = True
    if arch.video_processor and not tiny_vlms.has_torchvision():
        row["skipped"] = "processor needs torchvision"
        return row
    folder = built.save(work / arch.name)
    processor = built.processor()
    runs: dict[int, dict[str, str]] = {}
    # A first run renders the views into the shared snapshot cache, so the timed runs compare
    # generation alone.
    tiny_vlms.cli_run(work / f"{arch.name}-warm", folder, 8, "-M", f"dtype={dtype}")
    with tiny_vlms.encoded_prompts() as rows:
        for batch in (1, 8):
            start = time.perf_counter()
            tiny_vlms.cli_run(work / f"{arch.name}-b{batch}", folder, batch, "-M", f"dtype={dtype}")
            row[f"seconds_batch{batch}"] = round(time.perf_counter() - start, 2)
            runs[batch] = tiny_vlms.run_outputs(work / f"{arch.name}-b{batch}")
    seen = tiny_vlms.views_reaching_the_model(rows, processor.tokenizer, built.image_token_id)
    per_view = tiny_vlms.tokens_per_view(processor, built.image_token_id, "", size=448)
    row["image_tokens_per_view"] = per_view
    row["views_reach_model"] = all(
        s == [(view, per_view) for view in tiny_vlms.VIEWS] for s in seen
    )
    row["episodes"] = len(runs[1])
    row["batch8_equals_batch1"] = runs[8] == runs[1]
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="Write the rows as JSON here.")
    parser.add_argument("--only", action="append", help="Architecture name (repeatable).")
    args = parser.parse_args()
    device, dtype = _device()
    corpus = _corpus()
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        for arch in tiny_vlms.ARCHS:
            if args.only and arch.name not in args.only:
                continue
            try:
                rows.append(run_arch(arch, corpus, dtype, Path(tmp)))
            except Exception as exc:  # noqa: BLE001  (report every architecture, not the first)
                rows.append({"arch": arch.name, "error": f"{type(exc).__name__}: {exc}"[:400]})
            print(json.dumps(rows[-1]), flush=True)
    print(f"device: {device}, dtype {dtype}")
    for row in rows:
        print(
            f"{row['arch']:16} built={row.get('built', False)} "
            f"tokens/view={row.get('image_tokens_per_view', '-')} "
            f"views={row.get('views_reach_model', '-')} "
            f"b8==b1={row.get('batch8_equals_batch1', '-')} "
            f"s(b1,b8)=({row.get('seconds_batch1', '-')}, {row.get('seconds_batch8', '-')}) "
            f"{row.get('skipped', row.get('error', ''))}"
        )
    if args.out:
        args.out.write_text(json.dumps({"device": device, "dtype": dtype, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
