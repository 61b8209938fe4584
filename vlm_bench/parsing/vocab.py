"""Lookup tables built from the skill library: agents, skills, field values, and their aliases.

Everything the parser accepts comes from ``skills/*.json`` through :mod:`vlm_bench.catalog`;
nothing here lists a skill or a direction by hand. Spellings are compared after
:func:`token` (lower case, letters and digits only), so ``Front-Left``, ``front_left`` and
``FRONTLEFT`` are one token.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache

from vlm_bench.catalog.skills import skills
from vlm_bench.errors import DataFileError
from vlm_bench.types.skill import SkillField, SkillSpec

_NON_ALNUM = re.compile(r"[^a-z0-9]+")
_APOSTROPHES = re.compile(r"['’`]")

# Alternative JSON keys models use for the paper's keys (compared as tokens). Keys, not values:
# the allowed values all come from the skill library.
KEY_ALIASES: Mapping[str, str] = {
    "tasktype": "tasktype",
    "type": "tasktype",
    "agent": "tasktype",
    "skill": "skill",
    "action": "skill",
    "subtask": "subtask",
    "object": "object",
    "obj": "object",
    "objectid": "object",
    "target": "target",
    "targetobject": "target",
    "direction": "direction",
    "dir": "direction",
}


def token(text: str) -> str:
    """Lower-case ``text`` and drop everything but letters and digits."""
    return _NON_ALNUM.sub("", text.lower())


def object_id(text: str) -> str:
    """Snake-case an object reference: ``Rubik's Cube`` → ``rubiks_cube``."""
    return _NON_ALNUM.sub("_", _APOSTROPHES.sub("", text.lower())).strip("_")


@dataclass(frozen=True)
class Vocabulary:
    """Normalised lookups derived from the skill library."""

    agents: Mapping[str, str]
    """token(agent) → agent name (``uav`` → ``UAV``)."""
    skills: Mapping[str, SkillSpec]
    """token(name or alias) → skill."""
    skills_by_agent: Mapping[str, tuple[SkillSpec, ...]]
    """agent → its skills, in library order."""
    values: Mapping[tuple[str, str], Mapping[str, str]]
    """(skill, field) → token(value or alias) → canonical value, for closed-vocabulary fields."""
    agent_fields: Mapping[str, tuple[SkillField, ...]]
    """agent → union of its skills' fields by name, first declaration wins."""
    object_fields: tuple[str, ...]
    """Names of the fields that reference objects (``object``, ``target``)."""


def _add(table: dict[str, str], key: str, value: str, what: str) -> None:
    if table.get(key, value) != value:
        raise DataFileError(
            "skills/", f"{what} spelling {key!r} means both {table[key]!r} and {value!r}"
        )
    table[key] = value


def build_vocabulary(library: Mapping[str, SkillSpec]) -> Vocabulary:
    """Build the lookups; raises :class:`DataFileError` when an alias is ambiguous."""
    agents: dict[str, str] = {}
    skill_names: dict[str, str] = {}
    by_agent: dict[str, list[SkillSpec]] = {}
    values: dict[tuple[str, str], dict[str, str]] = {}
    for spec in library.values():
        _add(agents, token(spec.agent), spec.agent, "agent")
        by_agent.setdefault(spec.agent, []).append(spec)
        for spelling in (spec.name, *spec.aliases):
            _add(skill_names, token(spelling), spec.name, "skill")
        for fld in spec.fields:
            if fld.values is None:
                continue
            table = values.setdefault((spec.name, fld.name), {})
            for value in fld.values:
                _add(table, token(value), value, fld.name)
            for value, aliases in fld.value_aliases.items():
                for alias in aliases:
                    _add(table, token(alias), value, fld.name)
    agent_fields: dict[str, tuple[SkillField, ...]] = {}
    for agent, specs in by_agent.items():
        union: dict[str, SkillField] = {}
        for spec in specs:
            for fld in spec.fields:
                union.setdefault(fld.name, fld)
        agent_fields[agent] = tuple(union.values())
    object_fields = tuple(
        dict.fromkeys(f.name for s in library.values() for f in s.fields if f.type == "object")
    )
    return Vocabulary(
        agents=agents,
        agent_fields=agent_fields,
        object_fields=object_fields,
        skills={key: library[name] for key, name in skill_names.items()},
        skills_by_agent={agent: tuple(specs) for agent, specs in by_agent.items()},
        values=values,
    )


@cache
def vocabulary() -> Vocabulary:
    """The vocabulary of the shipped skill library (cached)."""
    return build_vocabulary(skills())


class SceneIds:
    """Matches normalised object references to a scene's ids (exact, after normalisation).

    A reference matches an id when both snake-case to the same string, or, failing that, when
    both are equal with separators removed (``RubiksCube`` → ``rubiks_cube``) and only one id of
    the scene has that form. Nothing fuzzier: ``red_cup`` does not match ``red_cup_1``.
    """

    def __init__(self, ids: Sequence[str] | None) -> None:
        self.known = ids is not None
        self._snake: dict[str, str] = {}
        compact: dict[str, list[str]] = {}
        for scene_id in ids or ():
            self._snake.setdefault(object_id(scene_id), scene_id)
            compact.setdefault(token(scene_id), []).append(scene_id)
        self._compact = {k: v[0] for k, v in compact.items() if len(set(v)) == 1}

    def resolve(self, reference: str) -> tuple[str, bool]:
        """Return (id, in_scene): the scene's id when matched, else the snake-cased reference."""
        snake = object_id(reference)
        if not self.known:
            return snake, True
        if snake in self._snake:
            return self._snake[snake], True
        compact = token(reference)
        if compact in self._compact:
            return self._compact[compact], True
        return snake, False
