"""The closed loop's rounds (docs/closed-loop.md): one pure round machine per episode that the
runner's pool, :func:`vlm_bench.vla.run_closed_loop` and a harness's solver all drive; an open
loop is the machine with no replans.

* :mod:`.machine`: :class:`RoundMachine`, a round's outcome in, the next action out
  (:class:`Execute`, :class:`Replan`, :class:`Done`).
* :mod:`.drive`: :func:`drive_episode` drives a machine synchronously on one live simulation.
* :mod:`.state`: what a replan plans from (:class:`ReplanRequest`, :class:`StateView`).
* :mod:`.replan_prompt`: a replan's generation request, its conversation and cache key.
"""

from vlm_bench.rounds.drive import drive_episode
from vlm_bench.rounds.machine import Done, Execute, Replan, RoundMachine
from vlm_bench.rounds.state import ReplanRequest, StateView

__all__ = [
    "Done",
    "Execute",
    "Replan",
    "ReplanRequest",
    "RoundMachine",
    "StateView",
    "drive_episode",
]
