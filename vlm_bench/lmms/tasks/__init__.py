"""lmms-eval task folders (YAML and their ``utils.py``), found through ``--include_path`` or
``LMMS_EVAL_PLUGINS=vlm_bench.lmms``."""
