"""lerobot's own ``LeRobotDataset`` reads a demos export, and its ACT policy trains on it.

lerobot (0.4.4, the newest for Python 3.11) pins torch < 2.11, torchvision and datasets < 5,
so it runs in its own virtual environment, never the project's. This script builds that
environment when it is missing (the commands are printed), writes a demos export of 2 tasks
x 5 train seeds unless one is given, and runs a check inside the environment that:

* loads the folder with ``LeRobotDataset(repo_id, root=..., video_backend="pyav")`` offline;
* compares fps, features (dtype and shape), frame and episode counts, each episode's
  length and task with what the export's own metadata says;
* decodes frames at episode boundaries;
* trains a tiny ACT (from scratch: no pretrained backbone) a few steps on CPU through
  lerobot's own pre-processor (normalisation from ``meta/stats.json``) and data loader.

Usage::

    python benchmarks/lerobot_check.py [--dataset DIR] [--venv DIR] [--steps 5]

Prints one JSON line with the findings; exits 1 when a check fails.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INSTALL = (
    ["-m", "pip", "install", "-q", "--upgrade", "pip"],
    ["-m", "pip", "install", "-q", "torch==2.9.1", "torchvision==0.24.1"],
    ["-m", "pip", "install", "-q", "lerobot==0.4.4"],
)
TASKS = ("standard_pick_place", "non_prehensile_push_cube")
SEEDS = "10-14"

# Runs inside lerobot's environment: argv[1] the dataset folder, argv[2] the training steps.
INNER = r"""
import json, sys, time
import torch
from lerobot.configs.types import FeatureType
from lerobot.datasets.lerobot_dataset import LeRobotDataset, LeRobotDatasetMetadata
from lerobot.datasets.utils import dataset_to_policy_features
from lerobot.policies.act.configuration_act import ACTConfig
from lerobot.policies.act.modeling_act import ACTPolicy
from lerobot.policies.factory import make_pre_post_processors

root, steps = sys.argv[1], int(sys.argv[2])
meta = LeRobotDatasetMetadata("vlm-bench/demos", root=root)
ds = LeRobotDataset("vlm-bench/demos", root=root, video_backend="pyav")
out = {
    "fps": ds.fps,
    "episodes": ds.num_episodes,
    "frames": ds.num_frames,
    "features": {k: [v["dtype"], list(v["shape"])] for k, v in ds.features.items()},
    "lengths": [int(e["length"]) for e in meta.episodes],
    "tasks": [list(e["tasks"]) for e in meta.episodes],
}
boundary = []
for e in meta.episodes:
    for i in (int(e["dataset_from_index"]), int(e["dataset_to_index"]) - 1):
        item = ds[i]
        images = [k for k in item if k.startswith("observation.images.")]
        boundary.append([int(item["episode_index"]), int(item["frame_index"]),
                         [list(item[k].shape) for k in images], item["task"]])
out["boundary_items"] = boundary

features = dataset_to_policy_features(meta.features)
outputs = {k: f for k, f in features.items() if f.type is FeatureType.ACTION}
inputs = {k: f for k, f in features.items() if k not in outputs}
cfg = ACTConfig(input_features=inputs, output_features=outputs, chunk_size=10,
                n_action_steps=10, dim_model=64, n_heads=4, dim_feedforward=128,
                n_encoder_layers=1, n_decoder_layers=1, n_vae_encoder_layers=1,
                pretrained_backbone_weights=None, device="cpu")
policy = ACTPolicy(cfg)
policy.train()
pre, _ = make_pre_post_processors(cfg, dataset_stats=meta.stats)
chunk = LeRobotDataset("vlm-bench/demos", root=root, video_backend="pyav",
                       delta_timestamps={"action": [i / ds.fps for i in range(cfg.chunk_size)]})
loader = torch.utils.data.DataLoader(chunk, batch_size=8, shuffle=True, num_workers=0)
optim = torch.optim.Adam(policy.parameters(), lr=1e-4)
losses, t0 = [], time.time()
for step, batch in enumerate(loader):
    if step >= steps:
        break
    loss, _ = policy.forward(pre(batch))
    optim.zero_grad()
    loss.backward()
    optim.step()
    losses.append(float(loss.item()))
out["act_losses"] = losses
out["act_params"] = sum(p.numel() for p in policy.parameters())
out["act_seconds"] = round(time.time() - t0, 1)
print("RESULT " + json.dumps(out))
"""


def build_venv(venv: Path) -> Path:
    """lerobot's environment at ``venv`` (made with the pinned installs when missing)."""
    python = venv / "bin" / "python"
    if (venv / ".lerobot-ready").is_file():
        return python
    steps = [[sys.executable, "-m", "venv", str(venv)], *([str(python), *c] for c in INSTALL)]
    for cmd in steps:
        print("$ " + " ".join(cmd), file=sys.stderr)
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if done.returncode:
            tail = (done.stderr or done.stdout).strip().splitlines()[-5:]
            sys.exit(f"cannot build lerobot's environment: {' '.join(cmd)}\n" + "\n".join(tail))
    (venv / ".lerobot-ready").write_text("torch 2.9.1, torchvision 0.24.1, lerobot 0.4.4\n")
    return python


def export(folder: Path) -> float:
    """Write the 2 tasks x 5 seeds export into ``folder``; returns the seconds it took."""
    args = ["export", "demos", str(folder), "--seeds", SEEDS, "--views", "wrist", "--size", "64"]
    for task in TASKS:
        args += ["--task", task]
    t0 = time.perf_counter()
    cmd = [sys.executable, "-c", "from vlm_bench.cli.main import main; main()", *args]
    subprocess.run([*cmd, "--no-progress"], check=True)
    return time.perf_counter() - t0


def expected(folder: Path) -> dict[str, object]:
    """What the export's own metadata says (read with the project's reader)."""
    from vlm_bench.vla.demos.reader import DemoDataset

    data = DemoDataset(folder)
    info = data.info
    return {
        "fps": info["fps"],
        "episodes": info["total_episodes"],
        "frames": info["total_frames"],
        "features": {k: [v["dtype"], list(v["shape"])] for k, v in info["features"].items()},
        "lengths": [int(e["length"]) for e in data.episodes],
        "tasks": [list(e["tasks"]) for e in data.episodes],
    }


def compare(got: dict[str, object], want: dict[str, object]) -> list[str]:
    """The checks that fail (empty: all hold)."""
    problems = [f"{k}: lerobot {got[k]!r} != export {v!r}" for k, v in want.items() if got[k] != v]
    boundary = got["boundary_items"]
    lengths = want["lengths"]
    assert isinstance(boundary, list) and isinstance(lengths, list)
    for k, length in enumerate(lengths):
        first, last = boundary[2 * k], boundary[2 * k + 1]
        if first[:2] != [k, 0] or last[:2] != [k, length - 1]:
            problems.append(f"episode {k}: boundary frames {first[:2]}, {last[:2]}")
    losses = got["act_losses"]
    if not isinstance(losses, list) or not losses:
        problems.append("ACT trained no step")
    return problems


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--dataset", type=Path, help="An existing demos export (default: make one)."
    )
    parser.add_argument("--venv", type=Path, default=ROOT / ".venv-lerobot")
    parser.add_argument("--steps", type=int, default=5, help="ACT training steps.")
    args = parser.parse_args()
    python = build_venv(args.venv)
    folder = args.dataset
    seconds = None
    if folder is None:
        folder = Path(tempfile.mkdtemp(prefix="demos-")) / "export"
        seconds = export(folder)
    env = {**os.environ, "HF_HUB_OFFLINE": "1", "HF_DATASETS_OFFLINE": "1"}
    done = subprocess.run(
        [str(python), "-c", INNER, str(folder), str(args.steps)],
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    lines = [x for x in done.stdout.splitlines() if x.startswith("RESULT ")]
    if done.returncode or not lines:
        sys.exit("lerobot's check failed:\n" + "\n".join(done.stderr.strip().splitlines()[-15:]))
    got = json.loads(lines[-1].removeprefix("RESULT "))
    problems = compare(got, expected(folder))
    got.pop("boundary_items")
    print(json.dumps({"dataset": str(folder), "export_s": seconds, **got, "problems": problems}))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
