"""Training data: planner SFT rows from train seeds (docs/training.md)."""

from vlm_bench.training.sft_dataset import SftExport, export_sft, sft_features
from vlm_bench.training.sft_rows import SftExample, sft_messages, target_text

__all__ = ["SftExample", "SftExport", "export_sft", "sft_features", "sft_messages", "target_text"]
