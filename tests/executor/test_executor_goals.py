"""Goal predicates on hand-built, physically settled states."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.goals import check_goals
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.sim.constants import part_joint
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.objects.builder_kit import free_joint_name
from vlm_bench.sim.scene import Scene, build_scene
from vlm_bench.types.task import Goal


def _place(scene: Scene, obj: str, xyz: tuple[float, float, float], tilt_deg: float = 0.0) -> None:
    """Put a free object at ``xyz`` (body origin = bottom centre), tilted about x, at rest."""
    joint = scene.model.joint(free_joint_name(obj))
    adr, dof = int(joint.qposadr[0]), int(joint.dofadr[0])
    half = math.radians(tilt_deg) / 2
    scene.data.qpos[adr : adr + 7] = [*xyz, math.cos(half), math.sin(half), 0.0, 0.0]
    scene.data.qvel[dof : dof + 6] = 0.0


def _settle(scene: Scene, seconds: float = 0.6) -> None:
    loop = SimLoop(scene)
    for _ in range(round(seconds / 0.05)):
        loop.control_step()


def _goal(pred: str, obj: str, target: str | None = None) -> Goal:
    return Goal(predicate=pred, object=obj, target=target)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def pick_place() -> Scene:
    return build_scene(get_episode("standard_pick_place", 0))


def test_inside_basket_true_after_settling_and_false_beside(pick_place: Scene) -> None:
    scene = pick_place
    basket = scene.data.body("yellow_basket").xpos.copy()
    goals = (
        _goal("inside", "gray_cube", "yellow_basket"),
        _goal("near", "gray_cube", "yellow_basket"),
        _goal("upright", "gray_cube"),
        _goal("off_surface", "gray_cube", "table"),
    )
    _place(scene, "gray_cube", (basket[0], basket[1], basket[2] + 0.06))
    _settle(scene)
    # Inside is not "near" (preposition_by_dont: next to the basket, not in it).
    assert check_goals(scene.episode, scene.model, scene.data, goals) == (True, False, True, False)
    # Beside the basket (0.24 m wide): centre 0.10 m from its footprint is near, 0.18 m is not.
    _place(scene, "gray_cube", (basket[0], basket[1] + 0.22, 0.751))
    _settle(scene)
    assert check_goals(scene.episode, scene.model, scene.data, goals) == (False, True, True, False)
    _place(scene, "gray_cube", (basket[0], basket[1] + 0.30, 0.751))
    _settle(scene)
    assert check_goals(scene.episode, scene.model, scene.data, goals) == (False, False, True, False)


def test_on_and_upright_and_off_surface(pick_place: Scene) -> None:
    scene = pick_place
    goals = (
        _goal("on", "gray_cube", "rubiks_cube"),
        _goal("stacked_on", "gray_cube", "rubiks_cube"),
        _goal("upright", "gray_cube"),
        _goal("off_surface", "gray_cube", "table"),
    )
    rubik = scene.data.body("rubiks_cube").xpos.copy()
    top = float(rubik[2]) + 0.057  # rubiks_cube height
    _place(scene, "gray_cube", (rubik[0], rubik[1], top + 0.002))
    _settle(scene)
    assert check_goals(scene.episode, scene.model, scene.data, goals) == (True, True, True, False)
    # On the floor, off the table's footprint and tipped over.
    _place(scene, "gray_cube", (0.0, 1.2, 0.03), tilt_deg=90.0)
    _settle(scene)
    assert check_goals(scene.episode, scene.model, scene.data, goals) == (False, False, False, True)


def test_drawer_and_knob_predicates() -> None:
    drawer = build_scene(get_episode("drawer_interaction", 0))
    goals = (_goal("drawer_open", "top_drawer"), _goal("drawer_closed", "top_drawer"))
    assert check_goals(drawer.episode, drawer.model, drawer.data, goals) == (False, True)
    adr = drawer.model.joint(part_joint("top_drawer")).qposadr[0]
    drawer.data.qpos[adr] = 0.36
    mujoco.mj_forward(drawer.model, drawer.data)
    assert check_goals(drawer.episode, drawer.model, drawer.data, goals) == (True, False)

    stove = build_scene(get_episode("hybrid_interaction_stove", 0))
    knob = (_goal("knob_rotated", "stove_knob"),)
    assert check_goals(stove.episode, stove.model, stove.data, knob) == (False,)
    stove.data.qpos[stove.model.joint(part_joint("stove_knob")).qposadr[0]] = np.radians(90.0)
    assert check_goals(stove.episode, stove.model, stove.data, knob) == (True,)


def test_unknown_ids_are_false(pick_place: Scene) -> None:
    goals = (_goal("near", "ghost", "yellow_basket"), _goal("drawer_open", "gray_cube"))
    assert check_goals(pick_place.episode, pick_place.model, pick_place.data, goals) == (
        False,
        False,
    )


def test_on_a_stove_is_measured_at_the_cooktop_not_at_its_knob() -> None:
    scene = build_scene(get_episode("hybrid_interaction_stove", 0))
    stove = scene.data.body("stove").xpos.copy()
    _place(scene, "white_bowl", (stove[0] - 0.1, stove[1] + 0.15, stove[2] + 0.795))
    _settle(scene)
    goal = (_goal("on", "white_bowl", "stove"),)
    assert check_goals(scene.episode, scene.model, scene.data, goal) == (True,)


def test_a_banana_across_a_bowl_is_inside_and_one_above_its_rim_is_not() -> None:
    scene = build_scene(get_episode("variant_banana_in_bowl", 0))
    bowl = scene.data.body("blue_bowl").xpos.copy()  # 0.16 m across, 0.07 m tall
    goal = (_goal("inside", "banana", "blue_bowl"),)
    # The 0.19 m banana cannot lie flat in the bowl: it rests on the rim, its middle sunk in.
    _place(scene, "banana", (bowl[0], bowl[1], bowl[2] + 0.05))
    _settle(scene, 1.0)
    bottom = float(object_bounds(scene.model, scene.data, "banana", solid_only=True)[0][2])
    assert bowl[2] + 0.035 < bottom < bowl[2] + 0.07 - 0.015  # above half height, below the rim
    assert check_goals(scene.episode, scene.model, scene.data, goal) == (True,)
    # Held level with its bottom just above the rim: over the bowl, but not in it.
    _place(scene, "banana", (bowl[0], bowl[1], bowl[2] + 0.075))
    mujoco.mj_forward(scene.model, scene.data)
    assert check_goals(scene.episode, scene.model, scene.data, goal) == (False,)
