"""The protocol of a perturbation kind (docs/design.md#how-to-add-a-perturbation-kind): a small
abstract class whose hooks the executor calls at the moments a kind can act.

A kind is constructed once per live episode with its rate (``--perturb name=rate``), the episode
and where to record the events that fire; it draws its own numbers, seeded by what happens (the
episode, the object, the n-th time), so two plans that do the same thing meet the same events
there. Every hook does nothing by default: a kind overrides those it needs (the base class
is not abstract for that reason).
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from typing import ClassVar

import numpy as np

from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.types.closed_loop import PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep


def event_rng(episode: Episode, kind: str, *key: object) -> np.random.Generator:
    """A random stream for one occasion of a kind: seeded by the episode (shared by both
    instruction variants), the kind and ``key`` (what happens: an object, a count...)."""
    text = "|".join(["perturb", kind, episode.task_id, str(episode.seed), *map(str, key)])
    digest = hashlib.sha256(text.encode()).digest()
    return np.random.default_rng(int.from_bytes(digest[:8], "big"))


class PerturbationKind:
    """One kind of perturbation (see module doc).

    Args:
        rate: The kind's ``--perturb`` value (a probability unless :attr:`maximum` says
            otherwise).
        episode: The episode being executed.
        emit: Records an event that fired (in the round's ``perturbations``).
    """

    name: ClassVar[str]
    """The ``--perturb`` key."""
    maximum: ClassVar[float | None] = 1.0
    """Largest value (None: any number >= 0)."""

    def __init__(self, rate: float, episode: Episode, emit: Callable[[PerturbEvent], None]):
        self.rate = rate
        self.episode = episode
        self.emit = emit

    def before_arm_step(self, loop: SimLoop, index: int, step: ArmStep) -> None:
        """An ARM step (plan index ``index``) is about to run."""

    def after_arm_step(self, loop: SimLoop, index: int, step: ArmStep, ok: bool) -> None:
        """An ARM step ran (``ok``: it succeeded)."""

    def flight_started(self, loop: SimLoop, index: int) -> None:
        """A UAV move (plan index ``index``) starts."""

    def flight_ended(self, loop: SimLoop) -> None:
        """The UAV move ended."""

    def between_rounds(self, loop: SimLoop, round_index: int) -> None:
        """Round ``round_index`` (1 = first replan) is about to run."""
