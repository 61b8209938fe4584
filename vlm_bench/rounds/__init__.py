"""The closed loop's rounds (docs/closed-loop.md): one pure round machine per episode that the
runner's pool, :func:`vlm_bench.vla.run_closed_loop` and a harness's solver all drive; an open
loop is the machine with no replans.

* :class:`RoundMachine`: a round's outcome in, the next action out (:class:`Execute`,
  :class:`Replan`, :class:`Done`).
* :func:`drive_episode`: drives a machine synchronously on one live simulation.
* :mod:`.replan_prompt`: a replan's generation request, its conversation and cache key.
"""

from vlm_bench.rounds.drive import Answer, DrivenEpisode, answer_steps, drive_episode
from vlm_bench.rounds.machine import Action, Done, Execute, Replan, RoundMachine, ran_steps
from vlm_bench.rounds.replan_prompt import Conversation, replan_generation_request
from vlm_bench.rounds.state import (
    ReplanRequest,
    RoundState,
    StateView,
    describe_state,
    round_outcome,
)

__all__ = [
    "Action",
    "Answer",
    "Conversation",
    "Done",
    "DrivenEpisode",
    "Execute",
    "Replan",
    "ReplanRequest",
    "RoundMachine",
    "RoundState",
    "StateView",
    "answer_steps",
    "describe_state",
    "drive_episode",
    "ran_steps",
    "replan_generation_request",
    "round_outcome",
]
