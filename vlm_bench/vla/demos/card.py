"""The dataset card (``README.md``) of a demos export: what it holds and how it was made."""

from __future__ import annotations

from vlm_bench.catalog.gt_episodes import MATERIALISED_SEEDS
from vlm_bench.vla.demos.config import DemoExportConfig, DemoExportSummary


def demos_card(config: DemoExportConfig, summary: DemoExportSummary, tasks: list[str]) -> str:
    """A Hugging Face dataset card in lerobot's style (YAML header, then the facts)."""
    seeds = sorted(set(config.seeds))
    tests = [s for s in seeds if s in MATERIALISED_SEEDS]
    failed = ", ".join(f"{n} {code}" for code, n in sorted(summary.failures.items())) or "none"
    split = (
        f"**Includes test seeds {', '.join(map(str, tests))}** (`--allow-test-seeds`): "
        "not a clean train split; do not evaluate on these seeds."
        if tests
        else "Train seeds only (10 and up): disjoint from the benchmark's test seeds 0-9."
    )
    shown = ", ".join(map(str, seeds)) if len(seeds) <= 10 else f"{seeds[0]} to {seeds[-1]}"
    unit = "ARM step" if config.per_arm_step else "task execution"
    v = config.variation
    return f"""---
task_categories:
- robotics
tags:
- LeRobot
- vlm-bench
configs:
- config_name: default
  data_files: data/*/*.parquet
---

# vlm-bench VLA demonstrations

Scripted executions of the benchmark's ground-truth plans (UAV + Franka Panda in MuJoCo),
recorded at 20 Hz as a LeRobotDataset v3.0 (`vlm-bench export demos`).

- {split}
- Seeds: {shown} ({len(seeds)}); tasks: {len(tasks)}.
- One episode per {unit}; task text: the {config.variant} instruction.
- Cameras: {", ".join(config.views) or "none"} at {config.size} px.
- Executions: {summary.executions}; kept (successful): {summary.kept}; left out: {failed}.
- Episodes: {summary.episodes}; frames: {summary.frames}.
- Variation: speed {v.speed[0]}-{v.speed[1]} m/s, acceleration {v.accel[0]}-{v.accel[1]}
  m/s², stow {v.stow_s[0]}-{v.stow_s[1]} s, hover offset ≤ {v.hover_xy_m} m horizontal and
  ±{v.hover_z_m} m vertical, heading ±{v.heading_deg}°, grasps shuffled: {v.shuffle_grasps}.
"""
