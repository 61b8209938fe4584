"""Vision-language-action use of the simulator: a learned policy drives the ARM steps.

Sits above :mod:`vlm_bench.executor` (it executes plans through :func:`execute_plan` and its
:class:`~vlm_bench.executor.SimLoop`); the runner never needs it.

* ``action``: the 12-D :class:`VlaAction` and how it is applied for one control period.
* ``observation``: the :class:`VlaObservation` (camera images, proprioception) a policy sees.
* ``hierarchical``: the :class:`Policy` protocol and :func:`policy_skills`, the ARM skills a
  policy drives inside a plan execution.
* ``closed_loop``: :func:`run_closed_loop`, a planner replanning after failed rounds in one
  simulation, the ARM steps driven by a policy (or the scripted skills).
* ``demos``: VLA demonstrations, the scripted executor's executions recorded as a LeRobot
  dataset (``vlm-bench export demos``, docs/demos.md).
* ``gym_env``: :class:`~vlm_bench.vla.gym_env.AerialManipulationEnv`, a gymnasium environment
  (imported on its own: it needs the ``gym`` extra).

The VLA metrics (S_pos, S_arm, S_safe) score every execution, scripted or not, so they live in
:mod:`vlm_bench.executor.vla_metrics`.
"""

from vlm_bench.vla.action import VlaAction, apply_action
from vlm_bench.vla.closed_loop import run_closed_loop
from vlm_bench.vla.hierarchical import PolicyOutput, grasped_object, policy_skills
from vlm_bench.vla.observation import Proprioception, VlaObservation

__all__ = [
    "PolicyOutput",
    "Proprioception",
    "VlaAction",
    "VlaObservation",
    "apply_action",
    "grasped_object",
    "policy_skills",
    "run_closed_loop",
]
