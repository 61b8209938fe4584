"""Skills' effect models, registered in one place.

A skill's data file names its model (``skills/<name>.json``: ``"effect": "hold"``); the GT
builder, the ``rules`` planner (and the few-shot examples), the closed loop's replan and the
executor's references read the model through :func:`effect_of`, so a skill's effect on the
planning state is written once. A new skill with a new kind of effect adds a class here.

| model | skill | where it works | what changes |
|---|---|---|---|
| ``hold`` | pick | its object | the gripper holds the object |
| ``release`` | place | where the held object will rest | the held object rests on/in the object |
| ``open`` | pull | the drawer's handle | the drawer is ``DRAWER_PULL`` open |
| ``shut`` | close | the drawer's handle | the drawer is shut |
| ``slide`` | push | its object | the object ends halfway to the target, or leaves its support |
| ``none`` | move, rotate | its object | nothing the plan's moves depend on |
"""

from __future__ import annotations

from vlm_bench.catalog.skills import skills
from vlm_bench.registry import Registry
from vlm_bench.rules.effects.base import PlanningState, SkillEffect, Xyz
from vlm_bench.rules.effects.drawers import SetOpening
from vlm_bench.rules.effects.holding import Hold, Release
from vlm_bench.rules.effects.sliding import Slide
from vlm_bench.rules.work import DRAWER_PULL

EFFECTS: Registry[SkillEffect] = Registry("skill effect model")
EFFECTS.add("none", SkillEffect())
EFFECTS.add("hold", Hold())
EFFECTS.add("release", Release())
EFFECTS.add("open", SetOpening(DRAWER_PULL))
EFFECTS.add("shut", SetOpening(0.0))
EFFECTS.add("slide", Slide())


def effect_of(skill: str) -> SkillEffect:
    """The effect model the skill ``skill`` names in its data file (a name the library does
    not know: ``none``).

    Raises:
        UnknownNameError: The skill names a model that is not registered (lists the valid ones).
    """
    spec = skills().get(skill)
    return EFFECTS.get(spec.effect) if spec is not None else EFFECTS.get("none")


__all__ = ["EFFECTS", "PlanningState", "SkillEffect", "Xyz", "effect_of"]
