"""The effect model of a skill: where its ARM step works and what it changes in a planner's
picture of the scene.

A planner's picture (:class:`PlanningState`) may be kept in any frame: the GT builder keeps one in
world coordinates from the episode, the ``rules`` planner one in the UAV's body frame from the
scene text. An effect model (:class:`SkillEffect`) is written once against the protocol and
serves both, and the closed loop's replan reads what it says about holding.
"""

from __future__ import annotations

from typing import ClassVar, Protocol

from vlm_bench.rules.approach import WorkPoint
from vlm_bench.types.plan import ArmStep

Xyz = tuple[float, float, float]
"""A point (m) in the state's own frame, z up."""


class PlanningState(Protocol):
    """What an effect model reads and changes in a planner's picture of the scene."""

    @property
    def held(self) -> str | None:
        """What the gripper holds."""

    def hold(self, item: str | None) -> None:
        """The gripper now holds ``item`` (None: nothing)."""

    def reference(self, item: str) -> WorkPoint | None:
        """Where an ARM step on ``item`` works (an object's centre, a part's handle), with its
        stand-off; None when the state does not know ``item``."""

    def height(self, item: str) -> float | None:
        """``item``'s height (m); None when the state does not know it."""

    def rest_on(self, item: str) -> Xyz | None:
        """Where the bottom of an object placed on or in ``item`` comes to rest; None when
        nothing can rest there or the state does not know ``item``."""

    def bottom(self, item: str) -> Xyz | None:
        """The bottom centre of object ``item``; None when the state does not know it."""

    def set_bottom(self, item: str, bottom: Xyz) -> None:
        """Object ``item`` now rests with its bottom centre at ``bottom``."""

    def is_drawer(self, item: str) -> bool:
        """Whether ``item`` is a drawer (it opens and closes)."""

    def set_opening(self, item: str, opening: float) -> None:
        """Drawer ``item`` is now open ``opening`` m (its handle and inside move with it)."""

    def remove(self, item: str) -> None:
        """Object ``item`` left its support (it no longer stands in the way of a flight)."""


class SkillEffect:
    """One skill's effect model (the base: it works at its object and changes nothing).

    A skill names its model in its data file (``skills/<name>.json``, ``effect``); models are
    registered by name in :mod:`vlm_bench.rules.effects`.
    """

    grasps: ClassVar[bool] = False
    """After the step, the gripper holds the step's object."""
    needs_held: ClassVar[bool] = False
    """The step acts on what the gripper holds (it is redone from the grasp if that fell)."""

    def work_point(self, state: PlanningState, step: ArmStep) -> WorkPoint | None:
        """Where the step works: its object's reference point (None: unknown object)."""
        return state.reference(step.object)

    def apply(self, state: PlanningState, step: ArmStep) -> None:
        """Change ``state`` as the step, done with success, changes the scene."""
