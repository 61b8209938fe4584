"""The benchmark as an lmms-eval task (``vlm_bench_aerial``, ``vlm_bench_aerial_text``), read
from a dataset folder ``vlm-bench export dataset`` wrote and scored by
:func:`vlm_bench.score_answer`.

lmms-eval finds the tasks with ``--include_path`` set to :data:`TASKS_DIR`, or as a plugin:
``LMMS_EVAL_PLUGINS=vlm_bench.lmms`` (it reads the ``tasks`` folder beside this module).
docs/dataset.md gives the commands.
"""

from vlm_bench.lmms.task_folder import TASKS_DIR

__all__ = ["TASKS_DIR"]
