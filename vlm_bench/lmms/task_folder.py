"""Where the lmms-eval task folders are."""

from pathlib import Path

TASKS_DIR = Path(__file__).resolve().parent / "tasks"
"""The folder to give lmms-eval's ``--include_path``."""
