"""VLA demonstrations: scripted executions of GT plans, varied like teleoperated ones,
recorded at the control rate and written as a LeRobotDataset v3.0 (docs/demos.md).

* ``variation``: the seeded speeds, hover offsets and grasp order of each demonstration.
* ``recorder``: the loop observer that turns the executor's commands into 12-D actions.
* ``record``: :func:`record_demo`, one recorded execution.
* ``lerobot_format`` / ``lerobot_writer``: the dataset layout and its streaming writer.
* ``export``: :func:`export_demos`, the ``vlm-bench export demos`` command's API.
* ``reader`` / ``replay``: an export read back from disk, and its actions replayed in the
  gym environment.
"""

from vlm_bench.vla.demos.config import DemoExportConfig, DemoExportSummary
from vlm_bench.vla.demos.export import export_demos
from vlm_bench.vla.demos.variation import DemoVariation

__all__ = ["DemoExportConfig", "DemoExportSummary", "DemoVariation", "export_demos"]
