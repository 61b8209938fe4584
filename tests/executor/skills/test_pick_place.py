"""End-to-end pick and place with real contacts (one known-good episode)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from incidents import incident_episode

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes import get_episode
from vlm_bench.executor.goals import check_goals
from vlm_bench.executor.live_episode import LiveEpisode, execute_plan
from vlm_bench.executor.motion import arm_core as arm_core_module
from vlm_bench.executor.motion.arm_planner import MAX_ASSIST, WORK_RADII
from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.motion.collision_check import CollisionQuery
from vlm_bench.executor.motion.lines import ArmLines
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills.grasping import GRASP_DESCENT, GRASP_TURN_ROOM, PRE_GRASP, Picker
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import PlanExecution
from vlm_bench.sim import constants as c
from vlm_bench.sim.objects import free_joint_name
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.robot import arm_qpos
from vlm_bench.sim.scene import build_scene
from vlm_bench.types.episode import Episode
from vlm_bench.types.world import ObjectKind


def test_gt_plan_container_geometry_bowl_seed0_reaches_goal() -> None:
    episode = get_episode("container_geometry_bowl", 0)
    scene = build_scene(episode)
    result = execute_plan(episode, episode.gt_plan, scene=scene)
    assert result.exec_success, result.failure_reason
    assert [s.status for s in result.steps] == ["ok", "ok", "ok"]
    loop = SimLoop(scene)
    for _ in range(20):  # settle 1 s
        loop.control_step()
    assert check_goals(episode, scene.model, scene.data) == (True,)


def test_place_without_pick_fails_with_reason() -> None:
    episode = get_episode("standard_pick_place", 0)
    plan = [episode.gt_plan[0], episode.gt_plan[2]]
    result = execute_plan(episode, plan)
    assert result.steps[1].status == "failed"
    assert result.failure_reason == "step 1: nothing held"


def test_planning_checks_the_held_object_too() -> None:
    """Collision checks move a held object with the hand: lowered until the cube (not the
    fingers) reaches into the table, only the check that carries it sees the table."""
    episode = get_episode("standard_pick_place", 0)
    scene = build_scene(episode)
    loop = SimLoop(scene)
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:2]):  # fly, pick the gray cube
        assert execution.step(i, step, episode.gt_plan).status == "ok"
    arm = Hand(loop)
    tcp, rot = arm.tcp()
    bottom = float(object_bounds(scene.model, scene.data, "gray_cube", solid_only=True)[0][2])
    table = float(object_bounds(scene.model, scene.data, "table", solid_only=True)[1][2])
    # TCP lowered so the cube's bottom sinks 1 cm into the table; the fingertips stay above.
    low = tcp - [0.0, 0.0, bottom - table + 0.01]
    q, res = arm.core.ik.solve(scene.data, low, rot, arm_qpos(scene.model, scene.data))
    assert res < 0.02
    table_geoms = arm.body_geoms("table")
    held = arm.body_geoms("gray_cube")
    bare = arm.core.collisions(q, CollisionQuery.of(held, c.GRIPPER_CLOSED))
    query = CollisionQuery.of(held, c.GRIPPER_CLOSED, None, arm.core.carried())
    carried = arm.core.collisions(q, query)
    assert not table_geoms & set(bare)
    assert table_geoms & set(carried)


def test_an_object_lost_on_the_way_to_the_release_fails_the_place(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Physics honesty: a place whose object drops out of the fingers on the way (here the
    gripper is made to open as the hand sets off towards the release) fails as slipped, not
    as a placed object."""
    from vlm_bench.executor.motion.joint_moves import hold_with_gripper

    episode = get_episode("standard_pick_place", 0)
    glide = ArmLines.glide

    def loose(lines: ArmLines, *args: object, **kwargs: object) -> bool:
        hold_with_gripper(lines.loop, 0.5, c.GRIPPER_OPEN)
        return glide(lines, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(ArmLines, "glide", loose)
    result = execute_plan(episode, episode.gt_plan)
    assert [s.status for s in result.steps] == ["ok", "ok", "failed"]
    assert result.failure_reason == "step 2: gray_cube slipped from the gripper"
    assert result.goals == (False,)


def test_a_held_object_is_carried_clear_of_what_the_flight_stops_at() -> None:
    """store_and_close seed 3: the cube, hanging where the pick lifted it, led the flight
    back to the open drawer and pushed it from 0.35 to 0.12 m shut. The arm now turns it
    aside first; the drawer stays open and the cube goes in (released over the part of the
    drawer out in front of the cabinet)."""
    from vlm_bench.sim.constants import part_joint

    episode = incident_episode("store_and_close", 3)
    scene = build_scene(episode)
    loop = SimLoop(scene)
    execution = PlanExecution(episode, loop, default_skills(loop))
    joint = scene.model.joint(part_joint("top_drawer")).qposadr[0]
    for i, step in enumerate(episode.gt_plan[:4]):  # fly, pick, climb, fly back to the cabinet
        assert execution.step(i, step, episode.gt_plan).status == "ok"
    assert loop.held == "rubiks_cube"
    assert float(scene.data.qpos[joint]) > 0.34
    outcome = execution.step(4, episode.gt_plan[4], episode.gt_plan)  # place in the drawer
    assert outcome.status == "ok", outcome.reason


def test_the_raise_after_a_pick_keeps_off_a_whipping_straight_line() -> None:
    """visual_combination_blue_red seed 4: raised straight up to carrying height, the arm's
    IK swung two joints 1.7 rad and drove the base joint onto its limit, and the cup fell out
    of the fingers. The raise now takes a straight line only where it is steady."""
    episode = incident_episode("visual_combination_blue_red", 4)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:2]):  # fly, pick the blue cup
        assert execution.step(i, step, episode.gt_plan).status == "ok"
    arm = Hand(loop)
    assert loop.held == "blue_cup"
    assert arm.touching_fingers("blue_cup")
    assert arm.core.ik.limit_margin(arm_qpos(loop.model, loop.data)) > 0.05


def test_a_steady_line_refuses_a_joint_whip() -> None:
    """The same 0.1 m raise is steady given 3 s and refused in 0.1 s, which would need a
    joint faster than 1 rad/s; nothing moves while it is previewed."""
    import numpy as np

    from vlm_bench.executor.motion.ik import TOP_DOWN_SEED
    from vlm_bench.executor.motion.joint_moves import joint_move

    loop = SimLoop(build_scene(get_episode("standard_pick_place", 0)))
    joint_move(loop, np.asarray(TOP_DOWN_SEED), 2.0, c.GRIPPER_OPEN)
    arm = Hand(loop)
    tcp, rot = arm.tcp()
    up = tcp + np.array([0.0, 0.0, 0.1])
    q = arm_qpos(loop.model, loop.data)
    assert arm.lines.steady_line(tcp, up, rot, 3.0, 1.0, margin=0.0) is not None
    assert arm.lines.steady_line(tcp, up, rot, 0.1, 1.0, margin=0.0) is None
    assert np.array_equal(arm_qpos(loop.model, loop.data), q)


def test_a_cleanser_held_by_its_cap_comes_up_in_the_hand() -> None:
    """function_detergent seed 4: the pads close on the cap's round sides, the nozzle beside
    them (no pad on its end), and the bottle comes up in the hand."""
    episode = incident_episode("function_detergent", 4)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:2]):  # fly, pick the cleanser
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert loop.held == "cleanser"
    assert Hand(loop).touching_fingers("cleanser")


def test_a_cup_closed_on_across_its_body_comes_up_without_spinning() -> None:
    """pick_left_cup_red seed 0: as the raise carried the cup, it slid 9 mm across the pads,
    and a pad's edge reached the line where it touched the cup's round (cylinder) collider;
    a contact normal turned along the pad's width and spun the cup to 71 rad/s (or to 27 rad/s,
    the cup 10 um elsewhere). The pads now close on the flat faces of the cup's wall."""
    episode = get_episode("pick_left_cup_red", 0)
    loop = SimLoop(build_scene(episode))
    spin = [0.0]

    def watch(lp: SimLoop) -> None:
        w = lp.data.joint(free_joint_name("red_cup_2")).qvel[3:]
        spin[0] = max(spin[0], float(np.abs(w).max()))

    loop.observers.append(watch)
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:2]):  # fly, pick the cup
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert loop.held == "red_cup_2"
    assert spin[0] < 5.0  # rad/s


def test_a_glide_that_drives_a_joint_onto_its_limit_is_refused() -> None:
    """variant_chocolate_box seed 2: the glide over the storage box ended with the base joint
    at its limit; the servo strayed and the release was missed by more than 6 cm. A glide
    reaching a limit is now refused, and the box goes in another way."""
    episode = incident_episode("variant_chocolate_box", 2)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason


def test_the_stow_keeps_the_wrist_out_of_the_uav(sideways_hand: Hand) -> None:
    """From an arm reaching out sideways, the straight joint-space stow swings link 6
    through the UAV's body; the stow goes through a via posture and touches nothing."""
    from vlm_bench.sim.robot import robot_geom_ids

    arm, loop = sideways_hand, sideways_hand.loop
    out = arm_qpos(loop.model, loop.data)  # the arm put out sideways
    stowed = np.asarray(c.ARM_STOW)
    query = CollisionQuery.of(set(), c.GRIPPER_OPEN, BaseMove.still())
    assert arm.core.path_hits(out, stowed, query) > 0
    robot = set(robot_geom_ids(loop.model))
    self_contacts = []

    def watch(lp: SimLoop) -> None:
        d = lp.data
        geoms = d.contact.geom[: d.ncon]
        self_contacts.extend(int(g1) for g1, g2 in geoms if g1 in robot and g2 in robot)

    loop.observers.append(watch)
    climb = arm.stow()
    assert not climb.any()
    assert self_contacts == []
    assert np.max(np.abs(arm_qpos(loop.model, loop.data) - stowed)) < 0.05


def test_the_stow_after_a_release_climbs_clear_of_a_mug_beside_it() -> None:
    """color_matched_sorting seed 8: folding up from the black mug's release, the elbow
    swept the yellow mug off the table (planned 3 cm clear). The UAV now climbs first,
    and the yellow mug stays upright for its own pick."""
    import math

    episode = incident_episode("color_matched_sorting", 8)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:3]):  # fly, pick the black mug, place it
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert not any(name.startswith("yellow_mug") for name in outcome.collisions)
    upright = float(loop.data.body("yellow_mug").xmat[8])
    assert math.degrees(math.acos(min(1.0, upright))) < 5.0


def test_a_flight_no_turn_clears_climbs_over_a_basket() -> None:
    """variant_green_nut seed 7: the pick left the arm reaching out low, and the flight to
    the workbench ended with the forearm in the yellow basket, knocking the nut in the hand
    onto its rim (it was let go outside). No turn of the base joint clears that flight, so
    the UAV climbs first and flies higher; nothing touches the basket until the place."""
    episode = incident_episode("variant_green_nut", 7)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    z0 = None
    for i, step in enumerate(episode.gt_plan[:3]):  # fly, pick the nut, fly to the basket
        if i == 2:
            z0 = float(loop.controller.setpoint[2])
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert not any(name.startswith("yellow_basket") for name in outcome.collisions)
    assert z0 is not None and loop.controller.setpoint[2] > z0 + 0.1
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason


def test_a_glide_over_a_release_keeps_a_flat_nut_in_the_fingers() -> None:
    """variant_green_nut seed 1: the nut, 1.6 cm tall, is gripped by its top few mm (the
    pads must stay above the table); the glide over the basket, turning the hand 70 degrees
    at 0.15 m/s, slid it 1.7 cm along the pads and out. The glide now goes at 0.1 m/s."""
    episode = incident_episode("variant_green_nut", 1)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan):  # fly, descend, pick, fly, place in the basket
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert all(check_goals(episode, loop.model, loop.data))


def test_a_bowl_held_by_its_rim_glides_without_turning() -> None:
    """stacking_nesting seed 3: the bowl, held by its rim 5 cm off its centre, pried the
    fingers open as the glide over the plate turned the hand 90 degrees, and fell. An object
    hanging that wide now glides with the hand's heading kept."""
    episode = incident_episode("stacking_nesting", 3)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:3]):  # fly, pick the bowl, place it on the plate
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert loop.held is None


def test_a_nut_beside_a_bin_wall_is_picked_across_two_flats() -> None:
    """contextual_spare_part seed 4: the nut's centre lay 6 cm out from the parts bin's wall;
    each of the four headings 90 degrees apart put the hand on the bin, and the pick closed on
    air. Of the six headings across a flat pair, one is clear."""
    episode = incident_episode("contextual_spare_part", 4)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    for i, step in enumerate(episode.gt_plan[:3]):  # fly, descend, pick the nut
        outcome = execution.step(i, step, episode.gt_plan)
        assert outcome.status == "ok", outcome.reason
    assert loop.held == "green_nut"


def test_a_place_prefers_a_way_down_clear_of_the_rim() -> None:
    """variant_chocolate_box seed 8: the way down into the storage box planned for the
    hand's heading passed the rim 1 mm off; the swaying arm hit it and stopped 6 cm short
    of the release. A heading whose way down keeps 1 cm clear is now preferred."""
    episode = incident_episode("variant_chocolate_box", 8)
    result = execute_plan(episode, episode.gt_plan)
    assert result.exec_success, result.failure_reason


def _picker_after_the_flight(task: str, seed: int) -> tuple[Episode, Picker]:
    """The episode (its incident scene) and a picker on its scene after the GT plan's first
    step (a UAV move)."""
    episode = incident_episode(task, seed)
    loop = SimLoop(build_scene(episode))
    execution = PlanExecution(episode, loop, default_skills(loop))
    assert execution.step(0, episode.gt_plan[0], episode.gt_plan).status == "ok"
    return episode, Picker(Hand(loop))


def _kind(episode: Episode, obj: str) -> ObjectKind:
    return object_kind(next(o.kind for o in episode.objects if o.id == obj))


def test_a_grasp_plan_checks_the_line_the_hand_takes() -> None:
    """variant_teddy_bear seed 4: the straight way down onto the bear took the arm far off
    the joint-space blend the plan had checked, and the elbow came down on the table. The
    grasp is now planned on the postures the line commands, and those touch nothing."""
    episode, picker = _picker_after_the_flight("variant_teddy_bear", 4)
    plan = picker.plan_grasp("teddy_bear", _kind(episode, "teddy_bear"))
    assert plan is not None
    reach, point = plan
    above = point + np.array([0.0, 0.0, PRE_GRASP])
    arm = picker.hand
    path = arm.lines.line_path(
        reach.q_start, above, point, reach.rotation, reach.q_end, reach.shift, GRASP_DESCENT
    )
    assert path is not None
    ignore = arm.body_geoms("teddy_bear")
    query = CollisionQuery.of(ignore, c.GRIPPER_OPEN, reach.shift)
    assert arm.core.hits_at(path, query) == 0
    result = execute_plan(episode, episode.gt_plan, scene=build_scene(episode))
    assert result.exec_success, result.failure_reason


def test_a_planned_move_is_checked_densely_along_the_hand(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """color_distractor_green seed 2: the arm's way to above the green cube, checked every
    0.1 rad of its widest joint swing, swept a finger through the yellow basket's rim between
    two checks; the pick landed on the rim. Checked every centimetre of the TCP's travel,
    that way counts contacts."""
    episode, picker = _picker_after_the_flight("color_distractor_green", 2)
    with monkeypatch.context() as patch:
        patch.setattr(arm_core_module, "PATH_TRAVEL", 10.0)  # joint-space spacing alone
        coarse = picker.plan_grasp("green_cube", _kind(episode, "green_cube"))
    assert coarse is not None and coarse[0].hits == 0
    core, data = picker.hand.core, picker.loop.data
    now = arm_qpos(picker.loop.model, data)
    basket = core.body_geoms("yellow_basket")
    query = CollisionQuery.of(set(), c.GRIPPER_OPEN, coarse[0].shift)
    assert core.path_hits(now, coarse[0].q_start, query) > 0
    seen = {
        g
        for q in core.joint_samples(now, coarse[0].q_start, coarse[0].shift)
        for g in core.collisions(q, query)
    }
    assert seen & basket


@pytest.mark.slow  # its outcome rests on contact physics another CPU's last bits may tip
@pytest.mark.xfail(
    strict=True,
    reason="the way to the grasp's start, checked every centimetre of the TCP's travel, still "
    "passes the left finger through the basket's back rim between two checks (u 0.913 and "
    "0.9275 of the move; it overlaps the rim over u 0.9167-0.926); at 500 Hz the lifted basket "
    "fell back, at 400 Hz (dc6bf8f) it stays on the hand and the grasp fails",
)
def test_the_densely_checked_pick_beside_the_basket_succeeds() -> None:
    """color_distractor_green seed 2 (the incident's scene): the pick planned with checks every
    centimetre succeeds."""
    episode = incident_episode("color_distractor_green", 2)
    result = execute_plan(episode, episode.gt_plan, scene=build_scene(episode))
    assert result.exec_success, result.failure_reason


def test_a_glide_is_checked_densely_along_the_hand() -> None:
    """tower_stacking seed 8: the arc glide carrying the gray cube to above the Rubik's cube,
    which sat in the yellow basket, swept the cube through the basket's rim between two of
    its 11 checks (7 cm apart) and dragged the basket 0.23 m; the cube was let go on the
    table. Checked every centimetre, that glide is refused, the plan's checked way takes the
    cube over the rim, and the basket stays where it was."""
    episode = incident_episode("tower_stacking", 8)
    live = LiveEpisode(episode)
    basket = np.array(live.loop.data.body("yellow_basket").xpos)
    result = live.execute(episode.gt_plan)
    assert result.exec_success, result.failure_reason
    assert np.linalg.norm(live.loop.data.body("yellow_basket").xpos - basket) < 0.01


def test_a_release_right_under_the_uav_is_reached_by_backing_off() -> None:
    """multi_object_sorting seed 1: the UAV stopped 1 cm from right above the gray basket,
    where no top-down reach gets (the elbow folds onto its limit), and every move to one of
    the working radii was longer than a skill may fly. The UAV now backs off as far as it
    may, and the cube is put in the basket."""
    episode = incident_episode("multi_object_sorting", 1)
    scene = build_scene(episode)
    arm = Hand(SimLoop(scene))
    base = scene.data.body(c.ARM_BASE_BODY).xpos
    point = base + np.array([0.002, 0.002, -0.7])  # 3 mm off right below the base
    moves = [m.xyz for m in arm.planner.assists(point)]
    level = [m for m in moves if m[2] == 0.0 and np.hypot(m[0], m[1]) > 0.0]
    assert level, "no horizontal move offered"
    assert max(float(np.linalg.norm(m)) for m in level) == pytest.approx(MAX_ASSIST)
    assert min(float(np.linalg.norm(m)) for m in level) <= WORK_RADII[0]
    result = execute_plan(episode, episode.gt_plan, scene=build_scene(episode))
    assert result.exec_success, result.failure_reason


def test_a_grasp_keeps_the_base_joint_off_its_limit() -> None:
    """variant_tomato_can seed 3: the can lay close under the arm base; the grasp posture
    left the base joint 0.09 rad off its limit, the lift and raise took it to 0.02, and no
    way to the bowl beside it was left but a swing that flung the can. A grasp with the base
    joint nearer its limit than GRASP_TURN_ROOM now counts as a contact, and the UAV moves
    for one with room."""
    episode, picker = _picker_after_the_flight("variant_tomato_can", 3)
    plan = picker.plan_grasp("tomato_can", _kind(episode, "tomato_can"))
    assert plan is not None
    reach, _ = plan
    assert reach.hits == 0
    ik = picker.hand.core.ik
    for q in (reach.q_start, reach.q_end):
        assert ik.room(q)[0] >= GRASP_TURN_ROOM
    result = execute_plan(episode, episode.gt_plan, scene=build_scene(episode))
    assert result.exec_success, result.failure_reason


def test_a_tall_object_is_set_down_standing_in_the_bowl() -> None:
    """slim_object_in_bowl seed 8: the 21 cm cleanser, let go 2 cm above the bowl's curved
    floor, rocked and toppled out over the rim. The hand now lowers it until it touches, so
    it stays standing inside."""
    episode = incident_episode("slim_object_in_bowl", 8)
    tilt: list[float] = []
    result = execute_plan(
        episode,
        episode.gt_plan,
        observers=[lambda loop: tilt.append(float(loop.data.body("cleanser").xmat[8]))],
    )
    assert result.exec_success, result.failure_reason
    assert tilt[-1] > math.cos(math.radians(20))  # standing, not leaning on the rim


def test_a_tall_object_is_centred_over_the_bowl_before_it_is_set_down() -> None:
    """slim_object_in_bowl seed 2: the cleanser hung 14 mm off the bowl's centre when the hand
    reached its release; set down there, a corner of its base (9.4 cm across, on a 9.6 cm
    floor) stood on the curved wall, it slid, toppled and tipped the bowl over. The hand now
    moves it over the centre first: it ends standing near there (leaning a few degrees on the
    wall, which 1 mm of slack leaves no way round), and the bowl stays level."""
    episode = incident_episode("slim_object_in_bowl", 2)
    last: dict[str, float] = {}

    def watch(loop: SimLoop) -> None:
        d = loop.data
        off = d.body("cleanser").xpos[:2] - d.body("yellow_bowl").xpos[:2]
        last["off"] = float(np.linalg.norm(off))
        last["bottle"] = float(d.body("cleanser").xmat[8])
        last["bowl"] = float(d.body("yellow_bowl").xmat[8])

    result = execute_plan(episode, episode.gt_plan, observers=[watch])
    assert result.exec_success, result.failure_reason
    assert last["off"] < 0.01
    assert last["bottle"] > math.cos(math.radians(10))
    assert last["bowl"] > math.cos(math.radians(5))


def test_a_planned_uav_turn_swings_the_arm_about_its_base() -> None:
    """A base move's yaw turns the UAV's heading (rad): IK and the collision checks see the
    arm, hung under the UAV's centre, turned about the vertical through its base;
    :meth:`Hand.shift_base` flies the turn and its undo brings the heading back."""
    episode = get_episode("drawer_interaction", 0)
    loop = SimLoop(build_scene(episode))
    arm = Hand(loop)
    data = loop.data
    q = arm_qpos(loop.model, data)
    base = np.array(data.body(c.ARM_BASE_BODY).xpos)
    tcp = arm.core.ik.tcp_at(data, q) - base
    for turn in (math.pi / 2, math.pi, -math.pi / 2):
        move = BaseMove(np.array([0.0, 0.0, 0.1]), turn)
        turned = arm.core.ik.tcp_at(data, q, move) - base
        cz, sz = math.cos(turn), math.sin(turn)
        expected = np.array([cz * tcp[0] - sz * tcp[1], sz * tcp[0] + cz * tcp[1], tcp[2] + 0.1])
        np.testing.assert_allclose(turned, expected, atol=1e-9)
    start = loop.uav_yaw_deg()
    up = BaseMove(np.array([0.0, 0.0, 0.1]), math.pi / 2)
    arm.shift_base(up)
    assert abs(math.remainder(loop.uav_yaw_deg() - start - 90.0, 360.0)) < 1.0
    arm.shift_base(up.undo())
    assert abs(math.remainder(loop.uav_yaw_deg() - start, 360.0)) < 1.0


def test_a_drawer_release_turns_the_uav_where_the_base_joint_cannot_reach() -> None:
    """drawer_interaction seed 3: the UAV faces the cabinet half a turn round from seed 0, and
    the base joint (5.8 rad of travel) leaves no way down into the open drawer that misses its
    front: the place failed, "top_drawer is out of reach". The hover above the drawer is now
    also planned with the UAV turned; it turns there, places the banana and turns back."""
    episode = incident_episode("drawer_interaction", 3)
    yaw: list[float] = []
    result = execute_plan(
        episode, episode.gt_plan, observers=[lambda loop: yaw.append(loop.uav_yaw_deg())]
    )
    assert result.exec_success, result.failure_reason
    turned = max(abs(math.remainder(y - yaw[0], 360.0)) for y in yaw)
    assert turned > 45.0
    assert abs(math.remainder(yaw[-1] - yaw[0], 360.0)) < 5.0
