"""Training data: planner SFT rows from train seeds (docs/training.md)."""

from vlm_bench.training.sft_dataset import export_sft
from vlm_bench.training.sft_rows import sft_messages, target_text

__all__ = ["export_sft", "sft_messages", "target_text"]
