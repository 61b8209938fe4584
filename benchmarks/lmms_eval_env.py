"""Install lmms-eval beside this environment, for the ``vlm_bench_aerial`` tasks' end-to-end test.

lmms-eval 0.7.3 requires torchvision, timm, wandb, sentence-transformers and more, which clash
with the project's CPU torch. Its command line with the OpenAI-compatible model needs none of
them: this installs lmms-eval without dependencies into a folder, with the few light packages
its command line imports that this environment lacks, to put on ``PYTHONPATH`` in front of this
environment (which supplies torch, transformers, datasets, openai and vlm-bench itself).

    python benchmarks/lmms_eval_env.py .lmms-eval        # then
    PYTHONPATH=.lmms-eval python -m lmms_eval eval --model openai ...

Prints the folder. Needs the package registry (pip).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

LMMS_EVAL = "lmms-eval==0.7.3"
"""The release tested."""

LIGHT_PACKAGES = (
    "accelerate",
    "loguru",
    "sacrebleu",
    "portalocker",
    "tabulate",
    "colorama",
    "lxml",
    "evaluate",
    "pytz",
    "aiohttp",
    "multidict",
    "yarl",
    "propcache",
    "aiohappyeyeballs",
    "aiosignal",
    "frozenlist",
    "python-dotenv",
    # lmms-eval patches filelock's 3.x internals (filelock._api), gone in 4.x.
    "filelock<4",
    # Its results table.
    "pytablewriter",
    "DataProperty",
    "mbstrdecoder",
    "pathvalidate",
    "tabledata",
    "tcolorpy",
    "typepy",
    "chardet",
)
"""What lmms-eval's command line, task loader and OpenAI model import beyond this
environment (found by importing them until nothing was missing)."""


def install(target: Path) -> Path:
    """Install lmms-eval and :data:`LIGHT_PACKAGES` into ``target`` (no dependencies)."""
    target.mkdir(parents=True, exist_ok=True)
    if (target / "lmms_eval").is_dir():
        return target
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--upgrade"]
    command += ["--target", str(target), LMMS_EVAL, *LIGHT_PACKAGES]
    subprocess.run(command, check=True)
    return target


if __name__ == "__main__":
    print(install(Path(sys.argv[1] if len(sys.argv) > 1 else ".lmms-eval").resolve()))
