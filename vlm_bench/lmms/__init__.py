"""The benchmark as an lmms-eval task (``vlm_bench_aerial``, ``vlm_bench_aerial_text``), read
from a dataset folder ``vlm-bench export dataset`` wrote and scored by
:func:`vlm_bench.score_answer`.

lmms-eval finds the tasks with ``--include_path`` set to :data:`TASKS_DIR`, or as a plugin:
``LMMS_EVAL_PLUGINS=vlm_bench.lmms`` (it reads the ``tasks`` folder beside this module).
docs/dataset.md gives the commands.
"""

from pathlib import Path

TASKS_DIR = Path(__file__).resolve().parent / "tasks"
"""The folder to give lmms-eval's ``--include_path``."""

__all__ = ["TASKS_DIR"]
