"""Prompt building: views, object list, instruction variants, images, hashes, golden snapshots."""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from vlm_bench.catalog.skills import skills
from vlm_bench.errors import ConfigError
from vlm_bench.prompting import build_prompt, prompt_config_hash, render_system, render_text
from vlm_bench.types.episode import Episode, EpisodeObject, Lighting, PartRef, UavPose
from vlm_bench.types.generation import GenerationRequest, ImagePart, RequestMeta, TextPart
from vlm_bench.types.plan import ArmStep, Direction, UavStep
from vlm_bench.types.prompt import ImageSlot, PromptConfig
from vlm_bench.types.task import Goal, Instructions

GOLDEN = Path(__file__).parent / "golden"
UPDATE = os.environ.get("VLM_BENCH_UPDATE_GOLDEN") == "1"
COLORS = {"uav": (200, 0, 0), "wrist": (0, 200, 0), "overhead": (0, 0, 200), "side": (90, 90, 90)}


def _png(color: tuple[int, int, int]) -> bytes:
    buf = io.BytesIO()
    Image.new("RGB", (8, 8), color).save(buf, format="PNG")
    return buf.getvalue()


IMAGES = {view: _png(c) for view, c in COLORS.items()}


def _episode(**changes: object) -> Episode:
    """A fixed synthetic episode (not a benchmark task): cube into basket, cabinet nearby."""
    objects = (
        EpisodeObject(
            id="gray_cube",
            kind="cube",
            color="gray",
            pos=(1.2, 0.8, 0.0),
            yaw_deg=0.0,
            on="floor",
            role="target",
        ),
        EpisodeObject(
            id="yellow_basket",
            kind="basket",
            color="yellow",
            pos=(1.5, 0.5, 0.0),
            yaw_deg=0.0,
            on="floor",
            role="destination",
        ),
        EpisodeObject(
            id="drawer_cabinet",
            kind="drawer_cabinet",
            color="white",
            pos=(-1.0, 0.0, 0.0),
            yaw_deg=0.0,
            on="floor",
            role="fixture",
        ),
    )
    episode = Episode(
        task_id="synthetic_pick_place",
        seed=3,
        suite="base_manipulation",
        environment="household_a",
        instructions=Instructions(
            explicit="Pick the gray cube and place it in the yellow basket.",
            implicit="Could you tidy the grey block away into the yellow container?",
        ),
        objects=objects,
        parts=(
            PartRef(id="top_drawer", parent="drawer_cabinet", kind="drawer", handle=(-0.8, 0, 0.9)),
        ),
        uav_start=UavPose(pos=(0.0, 0.0, 1.2), yaw_deg=0.0),
        lighting=Lighting(azimuth_deg=0.0, intensity=1.0),
        gt_plan=(
            UavStep(direction=Direction.FRONTLEFT),
            ArmStep(object="gray_cube", skill="pick"),
            ArmStep(object="yellow_basket", skill="place"),
        ),
        gt_uav_poses=(UavPose(pos=(1.0, 0.7, 0.6), yaw_deg=0.0),) * 3,
        goals=(Goal(predicate="inside", object="gray_cube", target="yellow_basket"),),
    )
    return episode.model_copy(update=changes)


def _check_golden(name: str, text: str) -> None:
    path = GOLDEN / name
    if UPDATE:
        path.write_text(text, encoding="utf-8")
        return
    assert path.is_file(), f"missing golden {path}; run with VLM_BENCH_UPDATE_GOLDEN=1"
    expected = path.read_text(encoding="utf-8")
    assert text == expected, f"{name} changed; review, then VLM_BENCH_UPDATE_GOLDEN=1 to accept"


def test_golden_system_prompt_without_examples() -> None:
    _check_golden("system_k0.txt", render_system(PromptConfig(k_shot=0)))


def test_golden_default_prompt() -> None:
    _check_golden("prompt_default.txt", render_text(build_prompt(_episode(), IMAGES)))


def test_golden_ablation_prompt() -> None:
    config = PromptConfig(
        k_shot=1, views=("uav",), object_list=False, instruction="implicit", few_shot_seed=7
    )
    _check_golden("prompt_ablation.txt", render_text(build_prompt(_episode(), IMAGES, config)))


def test_user_turn_labels_each_image_in_view_order() -> None:
    prompt = build_prompt(_episode(), IMAGES, PromptConfig(views=("side", "uav")))
    kinds = [type(p).__name__ for p in prompt.user]
    assert kinds == ["TextPart", "ImageSlot", "TextPart", "ImageSlot", "TextPart"]
    first, second = prompt.user[0], prompt.user[2]
    assert isinstance(first, TextPart) and first.text.endswith("(side):")
    assert isinstance(second, TextPart) and second.text.endswith("(uav):")
    assert prompt.views() == ["side", "uav"]
    assert set(prompt.images) == {"side", "uav"}  # dropped views are not carried


def test_object_list_and_instruction_variant() -> None:
    ep = _episode()
    prompt = build_prompt(ep, IMAGES)
    with_list = render_text(prompt)
    assert sorted(prompt.object_order) == sorted(ep.object_ids())
    assert f"Objects in the scene: {', '.join(prompt.object_order)}" in with_list
    assert ep.instructions.explicit in with_list
    without = render_text(
        build_prompt(ep, IMAGES, PromptConfig(object_list=False, instruction="implicit"))
    )
    assert "gray_cube" not in without.split("### user")[1]
    assert ep.instructions.implicit in without and ep.instructions.explicit not in without


def test_system_prompt_generated_from_skill_library() -> None:
    system = render_system(PromptConfig(k_shot=0))
    for spec in skills().values():
        assert f"- {spec.name} ({spec.agent} step): {spec.description}" in system
    for direction in Direction:
        assert direction.value in system
    assert "Output ONLY the JSON array" in system


def test_dropped_views_leave_the_system_prompt() -> None:
    system = render_system(PromptConfig(k_shot=0, views=("uav", "wrist")))
    assert "- uav:" in system and "- wrist:" in system
    assert "- overhead:" not in system and "- side:" not in system


def test_missing_image_is_a_config_error() -> None:
    with pytest.raises(ConfigError, match=r"no image for view.*wrist"):
        build_prompt(_episode(), {"uav": IMAGES["uav"]}, PromptConfig(views=("uav", "wrist")))


def test_images_may_be_pil_or_arrays_and_must_be_png() -> None:
    array = np.zeros((6, 6, 3), dtype=np.uint8)
    pil = Image.new("RGB", (6, 6), (1, 2, 3))
    prompt = build_prompt(
        _episode(), {"uav": pil, "wrist": array}, PromptConfig(views=("uav", "wrist"))
    )
    for data in prompt.images.values():
        assert data.startswith(b"\x89PNG")
    decoded = Image.open(io.BytesIO(prompt.images["uav"]))
    assert decoded.getpixel((0, 0)) == (1, 2, 3)
    with pytest.raises(ConfigError, match="not PNG"):
        build_prompt(_episode(), {"uav": b"GIF89a"}, PromptConfig(views=("uav",)))


def test_hash_tracks_the_rendered_text() -> None:
    base = build_prompt(_episode(), IMAGES)
    assert base.prompt_hash == build_prompt(_episode(), IMAGES).prompt_hash
    other_images = {v: _png((5, 5, 5)) for v in COLORS}
    assert build_prompt(_episode(), other_images).prompt_hash == base.prompt_hash
    implicit = build_prompt(_episode(), IMAGES, PromptConfig(instruction="implicit"))
    assert implicit.prompt_hash != base.prompt_hash
    assert prompt_config_hash(PromptConfig()) != prompt_config_hash(PromptConfig(k_shot=3))


def test_few_shot_examples_follow_the_episode_not_the_variant() -> None:
    explicit = build_prompt(_episode(), IMAGES, PromptConfig(k_shot=3))
    implicit = build_prompt(_episode(), IMAGES, PromptConfig(k_shot=3, instruction="implicit"))
    assert explicit.example_ids == implicit.example_ids and len(explicit.example_ids) == 3
    others = {
        build_prompt(_episode(seed=s), IMAGES, PromptConfig(k_shot=3)).example_ids for s in range(8)
    }
    assert len(others) > 1  # per-episode selection varies across episodes
    per_run = PromptConfig(k_shot=3, few_shot_selection="per_run")
    runs = {build_prompt(_episode(seed=s), IMAGES, per_run).system for s in range(4)}
    assert len(runs) == 1  # one system prompt for the whole run (prefix-cacheable)


def test_k_shot_zero_has_no_examples_section() -> None:
    prompt = build_prompt(_episode(), IMAGES, PromptConfig(k_shot=0))
    assert prompt.example_ids == () and "# Examples" not in prompt.system


def test_to_request_fills_image_slots_in_order() -> None:
    prompt = build_prompt(_episode(), IMAGES)
    meta = RequestMeta(task_id="synthetic_pick_place", object_ids=("gray_cube",))
    req = prompt.to_request("ep-1", meta=meta)
    images = req.images()
    assert [p.view for p in images] == ["uav", "wrist", "overhead", "side"]
    assert all(isinstance(p, ImagePart) and p.png == IMAGES[p.view] for p in images)
    assert req.system == prompt.system and req.episode_id == "ep-1" and req.meta == meta
    slots = [p for p in prompt.user if isinstance(p, ImageSlot)]
    assert len(slots) == len(images)


def test_requests_round_trip_through_json() -> None:
    req = build_prompt(_episode(), IMAGES).to_request(
        "ep-2", meta=RequestMeta(gt_plan=(UavStep(direction=Direction.UP),))
    )
    again = GenerationRequest.model_validate_json(req.model_dump_json())
    assert again == req and again.images()[0].png == IMAGES["uav"]


def test_object_list_is_shuffled_per_episode_target_first_as_often_as_chance() -> None:
    from vlm_bench.catalog.gt_episodes import load_materialised
    from vlm_bench.catalog.tasks import all_tasks, get_task
    from vlm_bench.prompting.builder import object_order

    first_is_target, chance = 0, 0.0
    episodes = [ep for t in all_tasks() for ep in load_materialised(t).episodes if ep.seed < 3]
    for ep in episodes:
        order = object_order(ep)
        assert sorted(order) == sorted(ep.object_ids())
        assert order == object_order(ep.model_copy())  # seeded: the same every time
        first_is_target += order[0] == ep.arm_steps()[0].object
        chance += 1 / len(order)
    # The task files list the target first in 40 of 60 tasks; shuffled, as often as chance
    # gives (about 1 in 6): neither favoured nor avoided.
    assert 0.6 * chance < first_is_target < 1.4 * chance, (first_is_target, chance)
    stored = load_materialised(get_task("standard_pick_place")).episodes
    orders = {tuple(object_order(ep)) for ep in stored[:6]}
    assert len(orders) > 1  # the order changes with the seed


def test_scene_as_text_lists_every_object_in_the_object_list_order() -> None:
    ep = _episode()
    prompt = build_prompt(ep, IMAGES, PromptConfig(scene_as_text=True))
    text = render_text(prompt)
    user = text.split("### user")[1]
    listed = [
        line.split(":")[0].split(" (")[0][2:] for line in user.splitlines() if line.startswith("- ")
    ]
    assert listed == list(prompt.object_order)
    assert "# The scene as text" in text
    assert "# The scene as text" not in render_text(build_prompt(ep, IMAGES))


def test_no_images_leaves_no_view_in_either_turn() -> None:
    prompt = build_prompt(_episode(), {}, PromptConfig(views=()))
    text = render_text(prompt)
    assert prompt.images == {} and prompt.views() == []
    assert "# The camera views" not in text and "<image:" not in text
    assert "Objects in the scene:" in text


def test_rule_numbers_in_the_prompt_are_the_ground_truths() -> None:
    """Each number the prompt states is computed here from the GT builder's own geometry and
    constants, independently of :func:`rule_numbers`; a drift in either fails."""
    import inspect
    import math

    from vlm_bench.catalog.world_catalog import object_kinds
    from vlm_bench.episodes.gt_builder import GroundTruthBuilder
    from vlm_bench.rules import work
    from vlm_bench.types.geometry import APPROACH, UAV_ROTOR_SPAN

    geo = inspect.signature(GroundTruthBuilder).parameters["geometry"].default
    assert geo is APPROACH  # the geometry episodes are built with
    system = render_system(PromptConfig(k_shot=0))
    reach = math.sqrt(geo.reach**2 - geo.op_height**2)
    standoff = math.sqrt(geo.ideal_standoff**2 - geo.op_height**2)
    (drawer,) = {p.standoff for k in object_kinds().values() for p in k.parts if p.kind == "drawer"}
    expected = [
        f"at most {reach:.2f} m from the UAV's centre, measured horizontally",
        f"comes within {standoff:.2f} m of the working point",
        f"({drawer:.2f} m for a drawer's handle or inside)",
        f"{geo.op_height + geo.arm_base_below_uav:.2f} m above the working point",
        f"by more than {geo.vertical_threshold:.2f} m",
        f"is {work.DRAWER_PULL:.2f} m open",
        f"({work.CONTAINER_FLOOR:.3f} m above its base)",
        f"{work.DRAWER_FLOOR_BELOW_HANDLE:.2f} m below its handle and "
        f"{work.DRAWER_INSIDE_BEHIND_HANDLE:.2f} m behind it (from the handle into the drawer",
        "horizontally at the destination's centre",
        f"The UAV is {UAV_ROTOR_SPAN:.2f} m across from rotor tip to rotor tip",
        "Each covers 45 degrees",
        '"up" comes before the step\'s horizontal move, "down" after it',
    ]
    for phrase in expected:
        assert phrase in system, phrase
