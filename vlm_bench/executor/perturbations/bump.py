"""``bump=P``: an ARM step's object is displaced before the step (docs/closed-loop.md).

Before an ARM step, with probability P its object (a free, movable object that is not held) is
displaced 0.2-0.4 m in a drawn horizontal direction, staying on what it rests on and clear of
other objects; objects resting on it move with it. Where no direction keeps it so (tried every
45 degrees from the drawn one), nothing is displaced.
"""

from __future__ import annotations

from collections.abc import Callable

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.executor.perturbations.kind import PerturbationKind, event_rng
from vlm_bench.executor.perturbations.placement import displace
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.types.closed_loop import PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep

BUMP_RANGE = (0.2, 0.4)
"""Horizontal displacement of a bump (m)."""


class Bump(PerturbationKind):
    """An ARM step's object is displaced before the step (module doc)."""

    name = "bump"

    def __init__(self, rate: float, episode: Episode, emit: Callable[[PerturbEvent], None]):
        super().__init__(rate, episode, emit)
        self._rng = event_rng(episode, self.name)

    def before_arm_step(self, loop: SimLoop, index: int, step: ArmStep) -> None:
        """Draw whether ``step``'s object is displaced, and displace it."""
        rng = self._rng
        draws = rng.random(), rng.uniform(*BUMP_RANGE), rng.uniform(0, 360)
        if draws[0] >= self.rate or not self._bumpable(loop, step.object):
            return
        shift = displace(loop, step.object, draws[1], draws[2])
        if shift is not None:
            self.emit(PerturbEvent(kind="bump", step=index, object=step.object, shift=shift))

    def _bumpable(self, loop: SimLoop, name: str) -> bool:
        obj = next((o for o in self.episode.objects if o.id == name), None)
        return obj is not None and object_kind(obj.kind).movable and loop.held != name
