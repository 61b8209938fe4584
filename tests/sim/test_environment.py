"""Environment variants: every one builds, renders, differs, keeps props out of the work area."""

from __future__ import annotations

import itertools

import mujoco
import numpy as np
import pytest
from numpy.typing import NDArray

from vlm_bench.catalog.world_catalog import environment, environments
from vlm_bench.sim.constants import FLOOR_GEOM
from vlm_bench.sim.environment import (
    FILL_LIGHT,
    KEY_GAIN,
    KEY_LIGHT,
    WALL_PREFIX,
    add_environment,
    key_light_direction,
)
from vlm_bench.sim.framing import view_xyaxes
from vlm_bench.sim.prop_kit import KEEP_OUT_RADIUS, PROP_PREFIX, PropPlacer
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.types.episode import Lighting

ENV_NAMES = sorted(environments())
NEUTRAL = Lighting(azimuth_deg=0.0, intensity=1.0)
CAM_POS = (2.5, -2.5, 2.2)


def build(name: str, lighting: Lighting = NEUTRAL) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """An environment with a red box at the origin and a camera looking at it."""
    spec = mujoco.MjSpec()
    add_environment(spec, environment(name), lighting)
    spec.worldbody.add_geom(
        name="target", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.2, 0.2, 0.2],
        pos=[0.0, 0.0, 0.2], rgba=[0.85, 0.12, 0.12, 1.0],
    )  # fmt: skip
    spec.worldbody.add_camera(
        name="dummy", pos=list(CAM_POS), xyaxes=view_xyaxes(-np.array(CAM_POS))
    )
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


@pytest.fixture(scope="module")
def images(renderer: SnapshotRenderer) -> dict[str, NDArray[np.uint8]]:
    out = {}
    for name in ENV_NAMES:
        model, data = build(name)
        out[name] = renderer.render(model, data, "dummy", 224)
    return out


def test_catalogue_has_six_variants_of_three_types() -> None:
    assert len(ENV_NAMES) == 6
    assert {environment(n).type for n in ENV_NAMES} == {"household", "industrial", "outdoor"}


@pytest.mark.parametrize("name", ENV_NAMES)
def test_environment_builds_with_floor_lights_and_visual_settings(name: str) -> None:
    model, _ = build(name)
    floor = model.geom(FLOOR_GEOM)
    assert floor.type[0] == mujoco.mjtGeom.mjGEOM_PLANE
    assert model.mat_texid[floor.matid[0], mujoco.mjtTextureRole.mjTEXROLE_RGB] >= 0
    assert any(model.tex_type[i] == mujoco.mjtTexture.mjTEXTURE_SKYBOX for i in range(model.ntex))
    assert model.vis.global_.offwidth >= 1024 and model.vis.global_.offheight >= 1024
    key = model.light(KEY_LIGHT)
    assert key.type[0] == mujoco.mjtLightType.mjLIGHT_DIRECTIONAL and key.castshadow[0]
    assert model.light(FILL_LIGHT).type[0] == mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    assert model.vis.headlight.diffuse.max() <= 0.15
    has_walls = any(model.geom(i).name.startswith(WALL_PREFIX) for i in range(model.ngeom))
    assert has_walls == environment(name).walls
    assert model.njnt == 0 and model.nbody == 1  # everything static, in the world body


@pytest.mark.parametrize("name", ENV_NAMES)
def test_environment_renders_non_blank(name: str, images: dict[str, NDArray[np.uint8]]) -> None:
    img = images[name]
    assert img.shape == (224, 224, 3) and img.dtype == np.uint8
    assert img.std() > 15.0
    assert 40.0 < img.mean() < 230.0  # neither black nor washed out
    centre = img[100:124, 100:124].astype(int)  # the red box at the origin
    assert (centre[..., 0] - centre[..., 2]).mean() > 60


def test_environments_look_different(images: dict[str, NDArray[np.uint8]]) -> None:
    for a, b in itertools.combinations(ENV_NAMES, 2):
        diff = np.abs(images[a].astype(int) - images[b].astype(int)).mean()
        assert diff > 8.0, (a, b, diff)


def _horizontal_clearance(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> float:
    """Horizontal distance from the origin to the geom's world-aligned bounding box."""
    centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
    corners = np.array(list(itertools.product(*[(-1.0, 1.0)] * 3))) * half + centre
    world = corners @ data.geom_xmat[geom].reshape(3, 3).T + data.geom_xpos[geom]
    lo, hi = world[:, :2].min(axis=0), world[:, :2].max(axis=0)
    nearest = np.clip(0.0, lo, hi)
    return float(np.linalg.norm(nearest))


@pytest.mark.parametrize("name", ENV_NAMES)
def test_props_are_static_visual_and_outside_the_work_area(name: str) -> None:
    model, data = build(name)
    decor = [
        i for i in range(model.ngeom) if model.geom(i).name.startswith((PROP_PREFIX, WALL_PREFIX))
    ]
    props = [i for i in decor if model.geom(i).name.startswith(PROP_PREFIX)]
    assert len(props) >= 15
    for i in decor:
        assert model.geom_bodyid[i] == 0
        assert model.geom_contype[i] == 0 and model.geom_conaffinity[i] == 0
        clearance = _horizontal_clearance(model, data, i)
        assert clearance > KEEP_OUT_RADIUS, (model.geom(i).name, clearance)


@pytest.mark.parametrize("name", ENV_NAMES)
def test_cameras_near_the_work_area_see_the_origin(name: str) -> None:
    model, data = build(name)
    target = model.geom("target").id
    hit = np.zeros(1, dtype=np.int32)
    for bearing, height in itertools.product(range(0, 360, 45), (0.8, 1.6, 2.6)):
        a = np.radians(bearing)
        pos = np.array([3.0 * np.cos(a), 3.0 * np.sin(a), height])
        direction = np.array([0.0, 0.0, 0.2]) - pos
        dist = mujoco.mj_ray(model, data, pos, direction, None, 1, -1, hit, None)
        assert dist > 0 and hit[0] == target, (bearing, height, model.geom(hit[0]).name)


def test_key_light_direction_turns_with_azimuth() -> None:
    env = environment("household_kitchen")
    base = np.array(key_light_direction(env, NEUTRAL))
    turned = np.array(key_light_direction(env, Lighting(azimuth_deg=90.0, intensity=1.0)))
    np.testing.assert_allclose(np.linalg.norm(turned), 1.0)
    np.testing.assert_allclose(turned, [-base[1], base[0], base[2]], atol=1e-12)


def test_lighting_jitter_changes_the_image() -> None:
    shadowed = SnapshotRenderer(shadows=True)  # the box's shadow moves with the azimuth

    def shot(lighting: Lighting) -> NDArray[np.float64]:
        model, data = build("outdoor_garden", lighting)
        key = model.light(KEY_LIGHT)
        assert key.diffuse[0] == pytest.approx(KEY_GAIN * 0.85 * lighting.intensity)
        return shadowed.render(model, data, "dummy", 224).astype(np.float64)

    with shadowed:
        base = shot(NEUTRAL)
        turned = shot(Lighting(azimuth_deg=120.0, intensity=1.0))
        dim = shot(Lighting(azimuth_deg=0.0, intensity=0.6))
        bright = shot(Lighting(azimuth_deg=0.0, intensity=1.3))
    assert np.abs(base - turned).mean() > 1.5
    assert dim.mean() + 10.0 < base.mean() < bright.mean() - 5.0


def test_unknown_variant_falls_back_to_its_type() -> None:
    bedroom = environment("household_living_room").model_copy(update={"name": "household_bedroom"})
    spec = mujoco.MjSpec()
    add_environment(spec, bedroom, NEUTRAL)
    model = spec.compile()
    assert sum(model.geom(i).name.startswith(PROP_PREFIX) for i in range(model.ngeom)) >= 15


@pytest.mark.parametrize(("axis", "expected"), [("x", (0.0, 1.0, 0.0)), ("y", (-1.0, 0.0, 0.0))])
def test_placer_turns_cylinders_onto_local_axes(axis: str, expected: tuple[float, ...]) -> None:
    spec = mujoco.MjSpec()
    placer = PropPlacer(spec, "prop/test/", (1.0, 2.0), yaw_deg=90.0)
    placer.cyl("rod", 0.05, 0.5, (1.0, 0.0, 0.3), "red", axis=axis)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    rod = model.geom("prop/test/rod").id
    np.testing.assert_allclose(data.geom_xpos[rod], [1.0, 3.0, 0.3], atol=1e-9)
    np.testing.assert_allclose(data.geom_xmat[rod].reshape(3, 3)[:, 2], expected, atol=1e-9)
