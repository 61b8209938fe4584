"""Shared test setup: headless rendering, golden-update flag."""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("HF_HUB_OFFLINE", "1")

UPDATE_GOLDEN = os.environ.get("VLM_BENCH_UPDATE_GOLDEN") == "1"
