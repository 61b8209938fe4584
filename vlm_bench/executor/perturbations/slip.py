"""``slip=P``: a held object drops during a flight (docs/closed-loop.md#perturbations).

When a flight starts with an object in the hand, with probability P the fingers open at a drawn
moment of the flight (its end, if it is shorter) and the object drops; the robot does not notice
until a skill needs it (``place`` fails ``slipped``).
"""

from __future__ import annotations

from collections.abc import Callable

from vlm_bench.executor.motion.joint_moves import hold_with_gripper
from vlm_bench.executor.perturbations.kind import PerturbationKind, event_rng
from vlm_bench.executor.perturbations.placement import in_fingers
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import GRIPPER_ACTUATOR, GRIPPER_OPEN
from vlm_bench.types.closed_loop import PerturbEvent
from vlm_bench.types.episode import Episode

SLIP_WINDOW_S = (0.3, 2.0)
"""Flight time at which a slip drops the object (s)."""
DROP_S = 0.6
"""Time the open fingers are held after a drop at a flight's end (s)."""


class Slip(PerturbationKind):
    """A held object slips out of the fingers during a flight (module doc)."""

    name = "slip"

    def __init__(self, rate: float, episode: Episode, emit: Callable[[PerturbEvent], None]):
        super().__init__(rate, episode, emit)
        self._rng = event_rng(episode, self.name)
        self._drop_at: float | None = None
        self._flight_start = 0.0
        self._step = 0

    def flight_started(self, loop: SimLoop, index: int) -> None:
        """Draw whether (and when) the held object drops."""
        self._drop_at = None
        if loop.held is None or not in_fingers(loop, loop.held):
            return  # nothing in the hand (a dropped object is gone until picked again)
        fires, at = self._rng.random() < self.rate, self._rng.uniform(*SLIP_WINDOW_S)
        if fires:
            self._drop_at, self._flight_start, self._step = loop.time + at, loop.time, index
            loop.observers.append(self._watch_flight)

    def _watch_flight(self, loop: SimLoop) -> None:
        if self._drop_at is not None and loop.time >= self._drop_at:
            self._drop(loop)

    def flight_ended(self, loop: SimLoop) -> None:
        """A drop still due happens now."""
        if self._drop_at is not None:
            self._drop(loop)
            hold_with_gripper(loop, DROP_S, GRIPPER_OPEN)
        if self._watch_flight in loop.observers:
            loop.observers.remove(self._watch_flight)

    def _drop(self, loop: SimLoop) -> None:
        held, self._drop_at = loop.held, None
        if held is None:
            return
        loop.data.ctrl[loop.model.actuator(GRIPPER_ACTUATOR).id] = GRIPPER_OPEN
        at = max(0.0, loop.time - self._flight_start)
        self.emit(PerturbEvent(kind="slip", step=self._step, object=held, at_s=round(at, 3)))
