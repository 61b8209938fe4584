"""Object builders: catalogue coverage, geometry, mass, contact stability, articulated parts."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from vlm_bench.catalog.world_catalog import object_kind, object_kinds
from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.sim.constants import object_geom, part_handle_site, part_joint
from vlm_bench.sim.objects import (
    OBJECT_BUILDERS,
    add_object,
    apply_initial_state,
    free_joint_name,
    geom_bounds,
    object_bounds,
)
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.types.episode import EpisodeObject

KINDS = sorted(object_kinds())
MOVABLE = [k for k in KINDS if object_kind(k).movable]
GRASPABLE = [k for k in KINDS if object_kind(k).graspable]
CONTAINERS = [k for k in KINDS if object_kind(k).container]
FIXTURES = [k for k in KINDS if not object_kind(k).movable]
SETTLE_S = 2.0


def place(
    kind: str, pos: tuple[float, float, float] = (0.0, 0.0, 0.0), **kw: object
) -> EpisodeObject:
    """An episode object of ``kind`` in its default colour."""
    fields: dict[str, object] = {
        "id": kind,
        "kind": kind,
        "color": object_kind(kind).default_color,
        "pos": pos,
        "yaw_deg": 0.0,
        "on": "floor",
        "role": "target",
    }
    fields.update(kw)
    return EpisodeObject.model_validate(fields)


def scene(*objs: EpisodeObject, floor: bool = True) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Compile the objects (and a floor plane); returns model and data after forward."""
    spec = mujoco.MjSpec()
    if floor:
        spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1])
    for obj in objs:
        add_object(spec, obj)
    model = spec.compile()
    data = mujoco.MjData(model)
    for obj in objs:
        apply_initial_state(model, data, obj)
    mujoco.mj_forward(model, data)
    return model, data


def simulate(model: mujoco.MjModel, data: mujoco.MjData, seconds: float) -> None:
    """Step ``seconds`` of physics; fails on NaNs or solver warnings."""
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
    assert np.isfinite(data.qpos).all()
    assert not any(w.number for w in data.warning), [w.number for w in data.warning]


def subtree_mass(model: mujoco.MjModel, name: str) -> float:
    root = model.body(name).id
    return float(model.body_subtreemass[root])


def tilt_deg(data: mujoco.MjData, name: str) -> float:
    """Angle between the body's z axis and the world's."""
    return math.degrees(math.acos(float(np.clip(data.body(name).xmat[8], -1.0, 1.0))))


def test_registry_matches_catalog_both_ways() -> None:
    assert set(OBJECT_BUILDERS.names()) == set(KINDS)
    assert len(OBJECT_BUILDERS) == len(KINDS)


def test_unknown_kind_lists_valid_kinds() -> None:
    spec = mujoco.MjSpec()
    obj = place("cube").model_copy(update={"kind": "spaceship"})
    with pytest.raises(UnknownNameError, match=r"valid: .*basket"):
        add_object(spec, obj)


@pytest.mark.parametrize("kind", KINDS)
def test_builds_alone_with_conventions(kind: str) -> None:
    model, _ = scene(place(kind, yaw_deg=0.0), floor=False)
    body = model.body(kind)
    assert body.parentid[0] == 0  # child of the world body
    free = model.joint(free_joint_name(kind)) if object_kind(kind).movable else None
    if object_kind(kind).movable:
        assert free is not None and free.type[0] == mujoco.mjtJoint.mjJNT_FREE
    else:
        assert body.jntnum[0] == 0  # fixtures are static
    prefixes = {kind, *(p.name for p in object_kind(kind).parts)}
    for g in subtree_geoms(model, body.id):
        assert model.geom(g).name.split("/")[0] in prefixes


@pytest.mark.parametrize("kind", KINDS)
def test_geometry_fits_bounding_box(kind: str) -> None:
    spec = object_kind(kind)
    model, data = scene(place(kind), floor=False)
    geoms = subtree_geoms(model, model.body(kind).id)
    if kind == "drawer_cabinet":  # bar handles protrude in front of the carcass (see world.json)
        geoms = [g for g in geoms if "handle" not in model.geom(g).name]
    boxes = [geom_bounds(model, data, g) for g in geoms]
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    size = np.asarray(spec.size)
    np.testing.assert_array_less(hi - lo, 1.05 * size + 1e-9)
    np.testing.assert_array_less(0.95 * size, hi - lo + 1e-9)
    assert np.all(np.abs((lo + hi)[:2] / 2) <= 0.025 * size[:2]), "footprint not centred"
    solid_lo, _ = object_bounds(model, data, kind, solid_only=True)
    assert abs(solid_lo[2]) < 1e-3, "origin is not at the bottom"


def test_cabinet_handles_end_just_past_their_sites() -> None:
    model, data = scene(place("drawer_cabinet"), floor=False)
    _, hi = object_bounds(model, data, "drawer_cabinet")
    handle_x = max(p.handle[0] for p in object_kind("drawer_cabinet").parts)
    assert handle_x < hi[0] <= handle_x + 0.012


@pytest.mark.parametrize("kind", KINDS)
def test_mass_matches_catalog(kind: str) -> None:
    model, _ = scene(place(kind), floor=False)
    assert subtree_mass(model, kind) == pytest.approx(object_kind(kind).mass, rel=0.1)


def test_two_objects_of_one_kind_coexist() -> None:
    a = place("cup", (0.0, 0.0, 0.0), id="red_cup_1")
    b = place("cup", (0.3, 0.0, 0.0), id="red_cup_2", color="blue")
    model, _ = scene(a, b)
    assert model.body("red_cup_1").id != model.body("red_cup_2").id
    assert model.geom(object_geom("red_cup_2", "shell")).id >= 0


@pytest.mark.parametrize("kind", MOVABLE)
def test_settles_on_the_floor(kind: str) -> None:
    obj = place(kind, (0.2, -0.1, 0.02), yaw_deg=30.0)
    model, data = scene(obj)
    start = data.body(kind).xpos.copy()
    simulate(model, data, SETTLE_S)
    lo, _ = object_bounds(model, data, kind, solid_only=True)
    assert -0.002 < lo[2] < 0.002, "sank into or floats above the floor"
    assert np.linalg.norm(data.body(kind).xpos[:2] - start[:2]) < 0.01
    assert tilt_deg(data, kind) < 8.0
    assert np.abs(data.qvel).max() < 0.02


@pytest.mark.parametrize("kind", [k for k in GRASPABLE if max(object_kind(k).size) < 0.25])
def test_settles_on_a_table(kind: str) -> None:
    top = object_kind("table").size[2]
    model, data = scene(place("table"), place(kind, (0.1, 0.1, top + 0.02), yaw_deg=-40.0))
    start = data.body(kind).xpos.copy()
    simulate(model, data, SETTLE_S)
    lo, _ = object_bounds(model, data, kind, solid_only=True)
    assert abs(lo[2] - top) < 0.002
    assert np.linalg.norm(data.body(kind).xpos[:2] - start[:2]) < 0.01
    assert tilt_deg(data, kind) < 8.0


def grasp_width(model: mujoco.MjModel, data: mujoco.MjData, body: str, depth: float) -> float:
    """Narrower horizontal extent of the solid geoms reaching into the top ``depth`` metres."""
    _, hi = object_bounds(model, data, body, solid_only=True)
    lows, highs = [], []
    for g in subtree_geoms(model, model.body(body).id, solid_only=True):
        g_lo, g_hi = geom_bounds(model, data, g)
        if g_hi[2] > hi[2] - depth:
            lows.append(g_lo)
            highs.append(g_hi)
    extent = np.max(highs, axis=0) - np.min(lows, axis=0)
    return float(min(extent[0], extent[1]))


@pytest.mark.parametrize("kind", GRASPABLE)
def test_graspable_fits_the_open_gripper(kind: str) -> None:
    """A top-down grasp reaches ~3.5 cm down; the Panda opens to 8 cm."""
    model, data = scene(place(kind), floor=False)
    if kind == "bowl":  # grasped by the rim: fingers straddle a thin wall
        walls = [
            g
            for g in subtree_geoms(model, model.body(kind).id, solid_only=True)
            if "wall_high" in model.geom(g).name
        ]
        assert walls and all(2 * model.geom_size[g][0] <= 0.015 for g in walls)
    else:
        assert grasp_width(model, data, kind, 0.035) <= 0.075
    for g in subtree_geoms(model, model.body(kind).id, solid_only=True):
        assert model.geom_condim[g] == 4
        assert 1.0 <= model.geom_friction[g][0] <= 1.5


def test_stove_knob_fits_the_open_gripper() -> None:
    model, data = scene(place("stove"), floor=False)
    assert grasp_width(model, data, "stove_knob", 0.035) <= 0.05


@pytest.mark.parametrize("kind", CONTAINERS)
@pytest.mark.parametrize("offset", [0.0, 0.3])
def test_cube_dropped_in_stays_inside(kind: str, offset: float) -> None:
    lx, ly, h = object_kind(kind).size
    x, y = offset * lx / 2, -offset * ly / 2
    cube = place("cube", (x, y, h + 0.05), id="small_cube", yaw_deg=15.0)
    model, data = scene(place(kind), cube)
    simulate(model, data, SETTLE_S)
    pos = data.body("small_cube").xpos
    lo, hi = object_bounds(model, data, kind, solid_only=True)
    cube_lo, _ = object_bounds(model, data, "small_cube", solid_only=True)
    assert lo[0] < pos[0] < hi[0] and lo[1] < pos[1] < hi[1]
    assert cube_lo[2] < min(h, 0.05), "rests on the rim or fell through"
    assert cube_lo[2] > -0.001


def test_drawer_slides_open_and_closed() -> None:
    model, data = scene(place("drawer_cabinet"))
    joint = model.joint(part_joint("middle_drawer"))
    assert joint.range.tolist() == pytest.approx([0.0, 0.40])
    qadr, dof = joint.qposadr[0], joint.dofadr[0]
    data.qfrc_applied[dof] = 40.0
    for _ in range(2000):
        mujoco.mj_step(model, data)
        if data.qpos[qadr] >= 0.35:
            break
    assert data.qpos[qadr] >= 0.35
    data.qfrc_applied[dof] = 0.0
    simulate(model, data, 0.5)  # friction holds it near where it was let go
    assert data.qpos[qadr] >= 0.34
    data.qfrc_applied[dof] = -40.0
    simulate(model, data, 2.0)
    assert data.qpos[qadr] < 0.005


def test_knob_turns_and_stays() -> None:
    model, data = scene(place("stove"))
    joint = model.joint(part_joint("stove_knob"))
    assert np.degrees(joint.range).tolist() == pytest.approx([0.0, 180.0])
    qadr, dof = joint.qposadr[0], joint.dofadr[0]
    data.qfrc_applied[dof] = 0.1
    for _ in range(2000):
        mujoco.mj_step(model, data)
        if data.qpos[qadr] >= math.radians(90.0):
            break
    data.qfrc_applied[dof] = 0.0
    released = float(data.qpos[qadr])
    assert released >= math.radians(90.0)
    simulate(model, data, 1.0)
    assert abs(data.qpos[qadr] - released) < math.radians(5.0)


@pytest.mark.parametrize("kind", ["drawer_cabinet", "stove"])
def test_handle_sites_at_catalog_offsets(kind: str) -> None:
    pos, yaw = (1.0, -2.0, 0.0), 90.0
    _, data = scene(place(kind, pos, yaw_deg=yaw))
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    for part in object_kind(kind).parts:
        hx, hy, hz = part.handle
        expected = (pos[0] + c * hx - s * hy, pos[1] + s * hx + c * hy, pos[2] + hz)
        site = data.site(part_handle_site(part.name)).xpos
        np.testing.assert_allclose(site, expected, atol=1e-9)


def test_initial_state_opens_drawer_and_turns_knob() -> None:
    cabinet = place("drawer_cabinet", initial={"top_drawer": 0.3})
    stove = place("stove", (2.0, 0.0, 0.0), initial={"stove_knob": 90.0})
    _, data = scene(cabinet, stove)
    site = data.site(part_handle_site("top_drawer")).xpos
    assert site[0] == pytest.approx(0.255 + 0.3)
    knob = data.body("stove_knob").xmat.reshape(3, 3)
    np.testing.assert_allclose(knob[:, 0], [0.0, 1.0, 0.0], atol=1e-9)  # pointer now along +y
    closed = data.site(part_handle_site("bottom_drawer")).xpos
    assert closed[0] == pytest.approx(0.255)


def test_initial_state_rejects_unknown_part_and_out_of_range() -> None:
    model, data = scene(place("drawer_cabinet"), floor=False)
    with pytest.raises(UnknownNameError, match="top_drawer"):
        apply_initial_state(model, data, place("drawer_cabinet", initial={"lid": 0.1}))
    with pytest.raises(ConfigError, match="outside"):
        apply_initial_state(model, data, place("drawer_cabinet", initial={"top_drawer": 0.9}))


def test_cube_stays_in_an_open_drawer() -> None:
    cabinet = place("drawer_cabinet", initial={"middle_drawer": 0.35})
    model, data = scene(cabinet)
    drawer = data.body("middle_drawer").xpos
    cube = place("cube", (float(drawer[0]), 0.0, float(drawer[2]) + 0.1), id="small_cube")
    model, data = scene(cabinet, cube)
    simulate(model, data, 1.0)
    local = data.body("middle_drawer").xmat.reshape(3, 3).T @ (
        data.body("small_cube").xpos - data.body("middle_drawer").xpos
    )
    assert abs(local[0]) < 0.2 and abs(local[1]) < 0.25 and -0.002 < local[2] < 0.05


def test_subtree_geoms_by_name_or_id_are_the_body_and_its_descendants() -> None:
    model, _ = scene(place("stove"), floor=False)  # a body with a part and visual-only geoms
    body = model.body("stove").id

    def below(b: int) -> bool:
        while b not in (body, 0):
            b = int(model.body_parentid[b])
        return b == body

    expected = [g for g in range(model.ngeom) if below(int(model.geom_bodyid[g]))]
    assert len({int(model.geom_bodyid[g]) for g in expected}) > 1  # the parts count too
    assert subtree_geoms(model, "stove") == subtree_geoms(model, body) == expected
    solid = subtree_geoms(model, body, solid_only=True)
    assert solid == [g for g in expected if model.geom_contype[g] or model.geom_conaffinity[g]]
    assert len(solid) < len(expected)  # visual-only geoms are left out
