"""The skill library (``skills/*.json``): data only; each skill's effect model is registered in
:mod:`vlm_bench.rules.effects` under the name its file gives."""

from __future__ import annotations

from functools import cache

from vlm_bench.catalog.files import load_by_name
from vlm_bench.errors import UnknownNameError
from vlm_bench.resources import skills_dir
from vlm_bench.types.skill import SkillSpec


@cache
def skills() -> dict[str, SkillSpec]:
    """All skills by canonical name, in file-name order (cached)."""
    return load_by_name(skills_dir(), SkillSpec, lambda spec: spec.name)


def skill(name: str) -> SkillSpec:
    """One skill by canonical name; raises listing the valid skills."""
    table = skills()
    if name not in table:
        raise UnknownNameError("skill", name, table)
    return table[name]


def arm_skill_names() -> list[str]:
    """Canonical names of the ARM skills."""
    return [s.name for s in skills().values() if s.agent == "ARM"]
