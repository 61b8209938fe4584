"""Normalise one plan element into a :class:`ParsedStep`.

Rules (documented choices):

* Keys are matched as tokens with a few aliases (``task_type``, ``type``, ``agent``, ``action``,
  ``obj``...); values are matched as tokens against the skill library's values and aliases.
* ``tasktype`` is required and never inferred: a step without it is invalid (``missing_field``)
  even if it carries a direction, because type accuracy (M of S_plan) is what the model must get
  right. Its case and separators are normalised (``uav``, ``Arm``).
* A step's skill must belong to its tasktype's agent. When the agent has one skill (UAV:
  ``move``) the ``skill`` key may be omitted; when given it must resolve to that skill
  (``fly``, ``move``) or the step is invalid (``unknown_skill``).
* Fields read are the union of the agent's skills' fields (as in the schema); required-ness is
  that of the resolved skill. String values ``""``, ``none``, ``null``, ``n/a`` mean absent.
  Every field a skill declares is kept: a skill declares only fields a plan step carries
  (:data:`~vlm_bench.types.skill.STEP_FIELDS`, checked when the skill file loads).
* An invalid step keeps whatever it resolved (tasktype, direction, skill, object, target) for
  the error taxonomy; scoring never credits it, and its object references count against S_obj.
  A valid UAV step carries no object references, even if the model wrote some.
"""

from __future__ import annotations

import math
import re
from typing import Any

from vlm_bench.parsing.vocab import KEY_ALIASES, SceneIds, Vocabulary, token
from vlm_bench.types.base import utf8_text
from vlm_bench.types.parse import ParseCode, ParsedStep
from vlm_bench.types.plan import Direction
from vlm_bench.types.skill import STEP_FIELDS, SkillField, SkillSpec

_DIRECTIONS = {d.value: d for d in Direction}
_NULLS = frozenset({"", "none", "null", "na", "nil"})
# One optional space run after the number (two adjacent ones backtrack quadratically).
_NUMBER = re.compile(r"^\s*(\d+(?:\.\d*)?|\.\d+)\s*(?:(?:m|meters?|metres?)\s*)?$", re.I)


def canonical_keys(raw: dict[str, Any]) -> dict[str, Any]:
    """Map the step's keys to canonical names; an exact canonical key wins over an alias."""
    out: dict[str, Any] = {}
    for key, value in raw.items():
        name = KEY_ALIASES.get(token(str(key)), token(str(key)))
        if name not in out or key == name:
            out[name] = value
    return out


def _text(value: str) -> str:
    """Join surrogate pairs and replace lone surrogates (JSON escapes can produce them)."""
    return utf8_text(value)


def json_safe(value: Any) -> Any:
    """``value`` made serialisable: non-finite floats → None, lone surrogates replaced."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, str):
        return _text(value)
    if isinstance(value, list):
        return [json_safe(v) for v in value]
    if isinstance(value, dict):
        return {_text(str(k)): json_safe(v) for k, v in value.items()}
    return value


def _absent(value: Any) -> bool:
    return value is None or (isinstance(value, str) and token(value) in _NULLS)


def _number(value: Any) -> float | None:
    if isinstance(value, int | float) and not isinstance(value, bool):
        number = float(value) if abs(value) < 1e300 else math.inf
    elif isinstance(value, str) and (match := _NUMBER.match(value)):
        number = float(match.group(1))
    else:
        return None
    return number if math.isfinite(number) and number > 0 else None


class _Reader:
    """Resolves one step's values, collecting error codes."""

    def __init__(self, fields: dict[str, Any], vocab: Vocabulary, scene: SceneIds) -> None:
        self.fields, self.vocab, self.scene = fields, vocab, scene
        self.errors: list[ParseCode] = []
        self.valid = True

    def fail(self, code: ParseCode, required: bool = True) -> None:
        self.errors.append(code)
        self.valid = self.valid and not required

    def agent(self) -> str | None:
        value = self.fields.get("tasktype")
        if _absent(value):
            self.fail(ParseCode.MISSING_FIELD)
            return None
        agent = self.vocab.agents.get(token(value)) if isinstance(value, str) else None
        if agent is None:
            self.fail(ParseCode.UNKNOWN_TASKTYPE)
        return agent

    def skill(self, agent: str) -> SkillSpec | None:
        own = self.vocab.skills_by_agent[agent]
        value = self.fields.get("skill")
        if _absent(value):
            if len(own) == 1:
                return own[0]
            self.fail(ParseCode.MISSING_FIELD)
            return None
        spec = self.vocab.skills.get(token(value)) if isinstance(value, str) else None
        if spec is None or spec.agent != agent:
            self.fail(ParseCode.UNKNOWN_SKILL)
            return None
        return spec

    def reference(self, name: str, required: bool) -> str | None:
        value = self.fields.get(name)
        if _absent(value):
            if required:
                self.fail(ParseCode.MISSING_FIELD)
            return None
        if not isinstance(value, str):
            self.fail(ParseCode.BAD_VALUE, required)
            return None
        ref, in_scene = self.scene.resolve(value)
        if not ref:
            self.fail(ParseCode.BAD_VALUE, required)
            return None
        if not in_scene:
            self.fail(ParseCode.UNKNOWN_OBJECT, required=False)
        return ref

    def value(self, skill: str, fld: SkillField, required: bool) -> Any:
        value = self.fields.get(fld.name)
        if _absent(value):
            if required:
                self.fail(ParseCode.MISSING_FIELD)
            return None
        if fld.type == "object":
            return self.reference(fld.name, required)
        if fld.type == "number":
            number = _number(value)
            if number is None:
                self.fail(ParseCode.BAD_VALUE, required)
            return number
        table = self.vocab.values.get((skill, fld.name), {})
        canonical = table.get(token(value)) if isinstance(value, str) else None
        if canonical is None:
            self.fail(ParseCode.UNKNOWN_DIRECTION, required)
        return canonical


def normalise_step(index: int, raw: Any, vocab: Vocabulary, scene: SceneIds) -> ParsedStep:
    """Normalise the plan element at ``index``; never raises."""
    if not isinstance(raw, dict):
        return ParsedStep(
            index=index,
            tasktype=None,
            valid=False,
            errors=(ParseCode.NOT_AN_OBJECT,),
            raw=json_safe(raw),
        )
    reader = _Reader(canonical_keys(raw), vocab, scene)
    agent = reader.agent()
    spec = reader.skill(agent) if agent is not None else None
    values: dict[str, Any] = {}
    if agent is not None:
        for fld in vocab.agent_fields[agent]:
            required = spec is not None and any(
                f.name == fld.name and f.required for f in spec.fields
            )
            skill_name = spec.name if spec is not None else vocab.skills_by_agent[agent][0].name
            values[fld.name] = reader.value(skill_name, fld, required)
        if spec is None:  # unknown skill: its required fields are unknown, but read what is there
            reader.valid = False
    if agent != "UAV" or not reader.valid:  # ARM and invalid steps: their references count
        for name in vocab.object_fields:
            if name not in values:
                values[name] = reader.reference(name, required=False)
    kept = {name: values.get(name) for fields in STEP_FIELDS.values() for name in fields}
    direction = kept.pop("direction")
    return ParsedStep(
        index=index,
        tasktype="UAV" if agent == "UAV" else "ARM" if agent == "ARM" else None,
        direction=_DIRECTIONS.get(direction) if isinstance(direction, str) else None,
        skill=spec.name if spec is not None else None,
        **kept,
        valid=reader.valid and agent is not None,
        errors=tuple(dict.fromkeys(reader.errors)),
        raw=json_safe(raw),
    )
