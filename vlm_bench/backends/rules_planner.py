"""``rules``: perfect perception (the scene as text) and perfect language, planned by the prompt's
rules alone — the ceiling that separates perception from planning.

It reads two things: the scene text in the prompt's user turn (``--scene-as-text``: every object's
position in the UAV body frame, what a perfect perceiver would read off the images) and the ARM
steps the instruction asks for (``RequestMeta.arm_steps``, what a perfect reader of the
instruction writes). Its UAV moves come from :func:`vlm_bench.rules.plan_from_scene`, the rules
the system prompt states. It never sees the episode: an import-linter contract forbids this
module to import ``vlm_bench.episodes``, ``vlm_bench.sim`` or ``vlm_bench.runner``. That it scores
100 on every task proves the prompt states everything the GT needs.
"""

from __future__ import annotations

from collections.abc import Sequence

from vlm_bench.backends.builtin import PlannerBackend
from vlm_bench.errors import ConfigError
from vlm_bench.rules import parse_scene, plan_from_scene, remaining_arm_steps
from vlm_bench.types.generation import GenerationRequest, TextPart
from vlm_bench.types.plan import ArmStep, UavStep

NO_SCENE = "backend 'rules' plans from the scene as text; run it with --scene-as-text"


def prompt_text(request: GenerationRequest) -> str:
    """The text of a request's user turn (images left out)."""
    return "\n".join(p.text for p in request.user if isinstance(p, TextPart))


class RulesBackend(PlannerBackend):
    """Plans from the prompt's scene text and rules (see module doc)."""

    name = "rules"

    def plan(self, request: GenerationRequest) -> Sequence[UavStep | ArmStep] | str:
        """The rules' plan for the request's scene text and ``meta.arm_steps``; in a closed
        loop's replan, for the ARM steps left to do (:func:`remaining_arm_steps`) from the
        scene text of the state now, holding ``meta.held``.

        Raises:
            ConfigError: The request has no scene text (the run lacks ``--scene-as-text``).
        """
        entries = parse_scene(prompt_text(request))
        if not entries:
            raise ConfigError(NO_SCENE)
        if request.meta is None or request.meta.arm_steps is None:
            return "rules: request has no meta.arm_steps"
        meta, arm_steps = request.meta, request.meta.arm_steps
        if meta.round == 0:
            return plan_from_scene(entries, arm_steps)
        _, rest = remaining_arm_steps(arm_steps, meta.done_steps, meta.held)
        return plan_from_scene(entries, rest, held=meta.held)
