"""Describe the machine a benchmark ran on (for the README)."""

from __future__ import annotations

import os
import platform
from pathlib import Path


def machine() -> str:
    """CPU model, core count and Python/MuJoCo versions, one line."""
    cpu = platform.processor() or "unknown CPU"
    info = Path("/proc/cpuinfo")
    if info.is_file():
        for line in info.read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    import mujoco

    gl = os.environ.get("MUJOCO_GL", "default")
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"MuJoCo {mujoco.__version__}, MUJOCO_GL={gl}"
    )
