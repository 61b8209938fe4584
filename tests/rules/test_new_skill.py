"""Adding a skill is its data file (and its executor function): what docs/design.md#how-to-add
lists. A copy of the shipped data with two more skill files is read in a fresh interpreter (the
skill library is cached per process) and every consumer picks them up: the prompt's skill
section, the plan JSON Schema, the parser, and the effect model the rules planner and the
replan use."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from vlm_bench.errors import DataFileError
from vlm_bench.resources import data_root
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.skill import STEP_FIELDS, SkillSpec

SCOOP = {  # grasps, as pick does: the effect model "hold"
    "name": "scoop",
    "agent": "ARM",
    "description": "Scoop loose material up with the gripper and hold it.",
    "aliases": ["ladle"],
    "fields": [
        {"name": "object", "type": "object", "required": True, "description": "What to scoop."}
    ],
    "effect": "hold",
}
WIPE = {  # changes nothing the moves depend on: "none"
    "name": "wipe",
    "agent": "ARM",
    "description": "Wipe a surface clean.",
    "fields": [
        {"name": "object", "type": "object", "required": True, "description": "The surface."}
    ],
    "effect": "none",
}

CHECKS = textwrap.dedent(
    """
    import json
    from vlm_bench.catalog.skills import skills
    from vlm_bench.parsing import parse_plan
    from vlm_bench.parsing.schema import plan_json_schema
    from vlm_bench.prompting.skills_section import skill_rows
    from vlm_bench.rules import SceneEntry, plan_segments, remaining_arm_steps
    from vlm_bench.rules.effects import effect_of
    from vlm_bench.types.plan import ArmStep

    out = {"skills": sorted(skills())}
    out["section"] = [row["name"] for row in skill_rows()]
    out["schema"] = json.dumps(plan_json_schema())
    parsed = parse_plan(
        '[{"tasktype": "ARM", "skill": "Ladle", "object": "sand"},'
        ' {"tasktype": "ARM", "skill": "place", "object": "bucket"}]',
        ["sand", "bucket"],
    )
    out["parsed"] = [[s.valid, s.skill, s.object] for s in parsed.steps]
    out["effects"] = {n: type(effect_of(n)).__name__ for n in ("scoop", "wipe")}
    scoop, place = ArmStep(object="sand", skill="scoop"), ArmStep(object="bucket", skill="place")
    out["replan"] = remaining_arm_steps([scoop, place], [scoop], None)[0]
    scene = [
        SceneEntry(id="sand", kind="object", point=(0.0, 2.0, -0.5), floor_height=0.8,
                   tall=0.1, rest=(0.0, 2.0, -0.45)),
        SceneEntry(id="bucket", kind="object", point=(2.0, 0.0, -0.5), floor_height=0.8,
                   tall=0.2, rest=(2.0, 0.0, -0.58)),
    ]
    segments = plan_segments(scene, [scoop, place])
    point = segments[1].point
    out["place_z"] = None if point is None else round(point.z, 3)
    print(json.dumps(out))
    """
)


def _data_with(tmp_path: Path, *extra: dict[str, object]) -> Path:
    """A data folder: the shipped one's, with ``extra`` skill files added to a copy of skills/."""
    root = tmp_path / "data"
    root.mkdir()
    for name in ("prompts", "ground_truth", "models"):
        (root / name).symlink_to(data_root() / name)
    (root / "skills").mkdir()
    for path in (data_root() / "skills").glob("*.json"):
        (root / "skills" / path.name).write_text(path.read_text())
    for skill in extra:
        (root / "skills" / f"{skill['name']}.json").write_text(json.dumps(skill))
    return root


def _run_checks(root: Path) -> dict[str, object]:
    env = {**os.environ, "VLM_BENCH_DATA_DIR": str(root)}
    done = subprocess.run(
        [sys.executable, "-c", CHECKS], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr[-3000:]
    result: dict[str, object] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def test_a_new_skill_file_reaches_prompt_schema_parser_and_effect_model(tmp_path: Path) -> None:
    out = _run_checks(_data_with(tmp_path, SCOOP, WIPE))
    assert {"scoop", "wipe"} <= set(out["skills"])  # type: ignore[arg-type]
    assert {"scoop", "wipe"} <= set(out["section"])  # type: ignore[arg-type]
    assert '"scoop"' in str(out["schema"]) and '"wipe"' in str(out["schema"])
    assert out["parsed"] == [[True, "scoop", "sand"], [True, "place", "bucket"]]
    assert out["effects"] == {"scoop": "Hold", "wipe": "SkillEffect"}
    # "hold": with nothing held any more, the place is redone from the scoop.
    assert out["replan"] == 0
    # "hold": the place works where the scooped object (0.1 m tall) will rest in the bucket,
    # not at the bucket's centre (z -0.5): -0.58 + 0.05.
    assert out["place_z"] == -0.53


def test_a_skill_naming_an_unknown_effect_model_is_refused(tmp_path: Path) -> None:
    out_of_order = {**WIPE, "effect": "teleport"}
    root = _data_with(tmp_path, out_of_order)
    env = {**os.environ, "VLM_BENCH_DATA_DIR": str(root)}
    code = "from vlm_bench.rules.effects import effect_of; effect_of('wipe')"
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60
    )
    assert done.returncode != 0
    assert "'teleport'" in done.stderr and "hold" in done.stderr  # lists the valid names


def test_a_skill_declares_only_fields_a_plan_step_carries() -> None:
    with pytest.raises(ValueError, match="not one that ARM plan steps carry"):
        SkillSpec.model_validate(
            {
                **WIPE,
                "fields": [
                    {"name": "force", "type": "number", "required": False, "description": "N"}
                ],
            }
        )
    # STEP_FIELDS are the step models' own fields, so a declared field is never dropped.
    for agent, model in (("UAV", UavStep), ("ARM", ArmStep)):
        assert set(STEP_FIELDS[agent]) == set(model.model_fields) - {"tasktype", "skill"}


def test_a_skill_file_with_an_uncarried_field_names_the_file(tmp_path: Path) -> None:
    bad = {
        **WIPE,
        "fields": [{"name": "force", "type": "number", "required": False, "description": "N"}],
    }
    root = _data_with(tmp_path, bad)
    env = {**os.environ, "VLM_BENCH_DATA_DIR": str(root)}
    code = "from vlm_bench.catalog.skills import skills; skills()"
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60
    )
    assert done.returncode != 0
    assert "wipe.json" in done.stderr and DataFileError.__name__ in done.stderr
