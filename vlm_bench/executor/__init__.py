"""Skill executor (docs/design.md#executor): executes validated plans in the simulator and
checks goals.

The wing is laid out by concept, each layer importing only those before it:

* ``vlm_bench.executor`` (this package): the plan execution (:func:`execute_plan`,
  ``live_episode``), the simulation loop (``sim_loop``), goal predicates (``goals``), the GT's
  reference points read live (``references``), the VLA metrics every execution is scored on
  (``vla_metrics``: the runner stores them, so they stay below :mod:`vlm_bench.vla`) and video.
* ``executor.motion``: how the robot moves, independent of any skill: IK, collision queries,
  base moves, joint moves, UAV flights, straight lines and glides, flight clearance, the stow
  and the arm planner.
* ``executor.skills``: the scripted ARM skills, one file per family (pick/place, push,
  articulation) over a shared hand core, and :func:`default_skills`.

Learned low-level policies and the gymnasium environment live above, in :mod:`vlm_bench.vla`.
"""

from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.executor.sim_loop import SimLoop, SimulatorUnstable
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.types.execution import ExecutionResult

__all__ = [
    "ExecutionResult",
    "SimLoop",
    "SimulatorUnstable",
    "default_skills",
    "execute_plan",
]
