"""The perturbations of one live episode: the configured kinds, each hook passed to each kind,
and the events that fired, in the order they fired."""

from __future__ import annotations

from vlm_bench.executor.perturbations.kind import PerturbationKind
from vlm_bench.executor.perturbations.registered import PERTURBATIONS
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.types.closed_loop import PerturbConfig, PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep


class Perturber:
    """Fires the episode's perturbations on one loop and keeps those that fired."""

    def __init__(self, config: PerturbConfig, episode: Episode) -> None:
        self.config = config
        self.episode = episode
        self.events: list[PerturbEvent] = []
        self.kinds: list[PerturbationKind] = [
            PERTURBATIONS.get(name)(rate, episode, self.events.append)
            for name, rate in config.rates().items()
            if rate > 0
        ]

    def before_arm_step(self, loop: SimLoop, index: int, step: ArmStep) -> None:
        """An ARM step is about to run."""
        for kind in self.kinds:
            kind.before_arm_step(loop, index, step)

    def after_arm_step(self, loop: SimLoop, index: int, step: ArmStep, ok: bool) -> None:
        """An ARM step ran."""
        for kind in self.kinds:
            kind.after_arm_step(loop, index, step, ok)

    def flight_started(self, loop: SimLoop, index: int) -> None:
        """A UAV move starts."""
        for kind in self.kinds:
            kind.flight_started(loop, index)

    def flight_ended(self, loop: SimLoop) -> None:
        """The UAV move ended."""
        for kind in self.kinds:
            kind.flight_ended(loop)

    def between_rounds(self, loop: SimLoop, round_index: int) -> None:
        """A replan's round is about to run."""
        for kind in self.kinds:
            kind.between_rounds(loop, round_index)
