"""Environment variants: floor, walls, sky, lights and decorative props (docs/design.md#world).

``add_environment`` dresses an ``MjSpec`` world as one of the catalogue's variants. Everything it
adds is static: the floor plane (named ``FLOOR_GEOM``) collides; walls (``wall/...``) and props
(``prop/...``) are visual only, so decoration never changes the benchmark's physics. Floor and wall
textures are generated from numpy arrays with a fixed seed, so renders are reproducible.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world_catalog import color
from vlm_bench.sim import prop_kit, props
from vlm_bench.sim.constants import FLOOR_GEOM
from vlm_bench.sim.materials import solid_material, textured_material, to_u8
from vlm_bench.types.base import RGBA
from vlm_bench.types.episode import Lighting
from vlm_bench.types.world import EnvironmentSpec

WALL_PREFIX = "wall/"
KEY_LIGHT = "key_light"
FILL_LIGHT = "fill_light"
WALL_HEIGHT = {"household": 2.8, "industrial": 4.2, "outdoor": 0.0}
OFFSCREEN_SIZE = 1024
SHADOW_MAP_SIZE = 2048
KEY_GAIN = 0.75  # catalogue diffuse -> MuJoCo diffuse, so key + fill + ambient stay below 1
FILL_DIFFUSE = 0.15
# The scene's extent is pinned (not computed from the far-away props) so that clip planes and
# the shadow map are sized for the scene: near 1 cm (wrist camera), far 150 m, shadows ±15 m
# (a smaller shadow box leaves speckles where the map ends; 2048² keeps texels ~15 mm).
SCENE_EXTENT = 5.0
_TEX_PX = 256
_OUTDOOR_GROUND_HALF = 40.0

Image = NDArray[np.uint8]


def add_environment(spec: mujoco.MjSpec, env: EnvironmentSpec, lighting: Lighting) -> None:
    """Add one environment variant to a scene under construction.

    Args:
        spec: The scene being built; its world body receives the floor, walls and props, its
            ``visual`` section the headlight, offscreen buffer and shadow settings.
        env: The environment variant from the world catalogue.
        lighting: The episode's lighting jitter (key-light azimuth and intensity).
    """
    _configure_visual(spec)
    _add_sky(spec, env)
    _add_floor(spec, env)
    if env.walls:
        _add_walls(spec, env)
    _add_lights(spec, env, lighting)
    props.add_props(spec, env)


def key_light_direction(env: EnvironmentSpec, lighting: Lighting) -> tuple[float, float, float]:
    """Unit direction of the key light: the variant's direction turned by the azimuth jitter."""
    dx, dy, dz = env.light.direction
    a = math.radians(lighting.azimuth_deg)
    x, y = dx * math.cos(a) - dy * math.sin(a), dx * math.sin(a) + dy * math.cos(a)
    norm = math.sqrt(x * x + y * y + dz * dz)
    return (x / norm, y / norm, dz / norm)


def _configure_visual(spec: mujoco.MjSpec) -> None:
    glob = spec.visual.global_
    glob.offwidth = max(glob.offwidth, OFFSCREEN_SIZE)
    glob.offheight = max(glob.offheight, OFFSCREEN_SIZE)
    spec.visual.quality.shadowsize = SHADOW_MAP_SIZE
    spec.stat.extent = SCENE_EXTENT
    spec.visual.map.znear = 0.01 / SCENE_EXTENT
    spec.visual.map.zfar = 150.0 / SCENE_EXTENT
    spec.visual.map.shadowclip = 15.0 / SCENE_EXTENT
    # The scene's own lights do the work; a faint headlight only lifts the darkest shadows.
    spec.visual.headlight.ambient = [0.0, 0.0, 0.0]
    spec.visual.headlight.diffuse = [0.08, 0.08, 0.08]
    spec.visual.headlight.specular = [0.0, 0.0, 0.0]


def _add_sky(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    spec.add_texture(
        name="env_sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=list(env.sky_top[:3]),
        rgb2=list(env.sky_bottom[:3]),
        width=256,
        height=256,
    )


def _add_floor(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    c1, c2 = color(env.floor_color), color(env.floor_color2)
    image, metres = floor_texture(env, c1, c2)
    mat = textured_material(
        spec, f"env_floor_{env.name}", image, (1.0 / metres, 1.0 / metres), True, specular=0.1
    )
    # Indoors the floor runs under the walls so no crack shows at their base.
    half = env.room_half_size + 0.2 if env.walls else _OUTDOOR_GROUND_HALF
    spec.worldbody.add_geom(
        name=FLOOR_GEOM,
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[half, half, 0.5],
        material=mat,
    )


def floor_texture(env: EnvironmentSpec, c1: RGBA, c2: RGBA) -> tuple[Image, float]:
    """The floor's texture image and the side length (m) one copy of it covers."""
    rng = np.random.default_rng(7)
    kind = env.floor_texture
    if kind == "checker" and env.type == "outdoor":
        return _pavers(to_u8(c1), to_u8(c2), rng), 2.4
    if kind == "checker":
        tile = 0.4 if env.type == "household" else 0.6
        return _checker(to_u8(c1), to_u8(c2), rng), 4 * tile
    if kind == "grid" and env.type == "household":
        return _planks(to_u8(c1), to_u8(c2), rng), 1.6
    if kind == "grid":
        return _grid(to_u8(c1), to_u8(c2), rng, line_px=5), 3.0
    if kind == "noise":
        return _noise(to_u8(c1), to_u8(c2), rng), 6.0
    return _mottle(np.broadcast_to(to_u8(c1), (_TEX_PX, _TEX_PX, 3)), rng, 6.0), 2.0


def _mottle(base: NDArray[np.generic], rng: np.random.Generator, amount: float) -> Image:
    noise = rng.normal(0.0, amount, base.shape[:2])[..., None]
    return np.clip(base.astype(np.float64) + noise, 0, 255).astype(np.uint8)


def _smooth_noise(rng: np.random.Generator, px: int, scale: float) -> NDArray[np.float64]:
    """Seamlessly tiling low-frequency noise in [-1, 1] (white noise low-passed by FFT)."""
    f = np.fft.fftfreq(px)
    radius = np.sqrt(f[:, None] ** 2 + f[None, :] ** 2)
    spectrum = np.fft.fft2(rng.normal(size=(px, px))) * np.exp(-((radius * scale) ** 2))
    field: NDArray[np.float64] = np.real(np.fft.ifft2(spectrum))
    return field / (float(np.abs(field).max()) + 1e-9)


def _checker(c1: Image, c2: Image, rng: np.random.Generator) -> Image:
    """4 × 4 tiles alternating two colours, each slightly shaded, with darker grout."""
    n, px = 4, _TEX_PX // 4
    img = np.empty((_TEX_PX, _TEX_PX, 3), dtype=np.float64)
    for i in range(n):
        for j in range(n):
            base = c1 if (i + j) % 2 == 0 else c2
            img[i * px : (i + 1) * px, j * px : (j + 1) * px] = base * rng.uniform(0.95, 1.03)
    grout = np.minimum(c1, c2) * 0.7
    for k in range(n):
        img[k * px : k * px + 2, :] = grout
        img[:, k * px : k * px + 2] = grout
    return _mottle(img, rng, 3.0)


def _planks(c1: Image, c2: Image, rng: np.random.Generator) -> Image:
    """Floorboards: 8 rows of staggered planks mixing two wood tones, with grain and seams."""
    rows, px = 8, _TEX_PX // 8
    img = np.empty((_TEX_PX, _TEX_PX, 3), dtype=np.float64)
    grain = 0.06 * np.sin(np.linspace(0, 40 * np.pi, _TEX_PX))[None, :]
    for r in range(rows):
        cut = int(rng.integers(0, _TEX_PX))
        for a, b in ((0, cut), (cut, _TEX_PX)):
            mix = rng.uniform(0.0, 1.0)
            tone = c1 * mix + c2 * (1.0 - mix)
            band = img[r * px : (r + 1) * px, a:b]
            band[:] = tone * (1.0 + grain[:, a:b, None] * rng.uniform(0.5, 1.5))
        img[r * px : r * px + 2, :] *= 0.55
        img[r * px : (r + 1) * px, max(cut - 1, 0) : cut + 1] *= 0.55
    return _mottle(img, rng, 4.0)


def _grid(c1: Image, c2: Image, rng: np.random.Generator, line_px: int) -> Image:
    """A mottled slab with lines along its edges (expansion joints or painted floor lines)."""
    img = c1.astype(np.float64) * (1.0 + 0.06 * _smooth_noise(rng, _TEX_PX, 12.0))[..., None]
    img[:line_px, :] = c2
    img[:, :line_px] = c2
    return _mottle(img, rng, 5.0)


def _noise(c1: Image, c2: Image, rng: np.random.Generator) -> Image:
    """Grass: mostly the first colour, patches of the second, darker tufts and blade noise."""
    px = 2 * _TEX_PX
    mix = np.clip(0.7 + 0.45 * _smooth_noise(rng, px, 24.0), 0.0, 1.0)[..., None]
    shade = (0.88 + 0.1 * _smooth_noise(rng, px, 6.0))[..., None]
    img = (c1 * mix + c2 * (1.0 - mix)) * shade
    return _mottle(img, rng, 10.0)


def _pavers(c1: Image, c2: Image, rng: np.random.Generator) -> Image:
    """Paving slabs in stretcher bond (rows offset by half a slab), two tones, dark joints."""
    n, px = 4, _TEX_PX // 4
    img = np.empty((_TEX_PX, _TEX_PX, 3), dtype=np.float64)
    joint = np.minimum(c1, c2) * 0.6
    for r in range(n):
        shift = px // 2 if r % 2 else 0
        for k in range(n):
            base = c1 if (r + k) % 2 == 0 else c2
            cols = (np.arange(k * px, (k + 1) * px) + shift) % _TEX_PX
            img[r * px : (r + 1) * px, cols] = base * rng.uniform(0.93, 1.04)
            img[r * px : (r + 1) * px, cols[:3]] = joint
        img[r * px : r * px + 3, :] = joint
    return _mottle(img, rng, 5.0)


def _add_walls(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Four walls at ``room_half_size`` with skirting (or dado) and windows."""
    hs, t = env.room_half_size, 0.05
    h = WALL_HEIGHT[env.type]
    wall = _wall_material(spec, env)
    trim = solid_material(spec, "env_trim", _shade(color(env.wall_color), 0.6), specular=0.1)
    world = spec.worldbody
    for side, (x, y, yaw) in _WALL_SIDES.items():
        quat = _yaw_quat(yaw)
        pos = [x * (hs + t), y * (hs + t), h / 2]
        world.add_geom(
            name=f"{WALL_PREFIX}{side}", type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[t, hs + 2 * t, h / 2], pos=pos, quat=quat, material=wall,
            contype=0, conaffinity=0,
        )  # fmt: skip
        # Skirting board at home; a darker dado with a yellow guard stripe in industrial halls.
        bands = [("skirting", 0.06, 0.06, trim)]
        if env.type == "industrial":
            stripe = solid_material(spec, "env_stripe", color("yellow"), specular=0.1)
            bands = [("dado", 0.6, 0.6, trim), ("stripe", 1.22, 0.04, stripe)]
        for k, (part, z, half_h, mat) in enumerate(bands):
            inset = hs - 0.01 - 0.002 * k
            world.add_geom(
                name=f"{WALL_PREFIX}{side}_{part}", type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[0.012, hs, half_h], pos=[x * inset, y * inset, z], quat=quat,
                material=mat, contype=0, conaffinity=0,
            )  # fmt: skip
    if env.type == "household":
        prop_kit.add_window(spec, f"{WALL_PREFIX}window_n", (0.0, hs), 90.0, (1.8, 1.2), 1.65)
        prop_kit.add_window(spec, f"{WALL_PREFIX}window_w", (-hs, 1.2), 0.0, (1.4, 1.2), 1.65)
    else:  # high strip windows of a hall
        for i, x in enumerate((-2.0, 2.0)):
            prop_kit.add_window(
                spec, f"{WALL_PREFIX}window_n{i}", (x, hs), 90.0, (3.0, 0.8), h - 0.7
            )
            prop_kit.add_window(
                spec, f"{WALL_PREFIX}window_s{i}", (x, -hs), 90.0, (3.0, 0.8), h - 0.7
            )


# side -> (unit x, unit y, yaw of the wall's normal axis in degrees)
_WALL_SIDES = {
    "east": (1.0, 0.0, 0.0),
    "west": (-1.0, 0.0, 0.0),
    "north": (0.0, 1.0, 90.0),
    "south": (0.0, -1.0, 90.0),
}


def _wall_material(spec: mujoco.MjSpec, env: EnvironmentSpec) -> str:
    """Painted plaster indoors at home; vertical steel panels in industrial halls."""
    base = to_u8(color(env.wall_color))
    rng = np.random.default_rng(11)
    if env.type == "industrial":
        img = np.broadcast_to(base, (_TEX_PX, _TEX_PX, 3)).astype(np.float64)
        ribs = 1.0 + 0.12 * np.sign(np.sin(np.linspace(0, 8 * np.pi, _TEX_PX)))
        img = img * ribs[None, :, None]
        return textured_material(spec, "env_wall", _mottle(img, rng, 3.0), (0.5, 0.5), True)
    img = np.broadcast_to(base, (_TEX_PX, _TEX_PX, 3))
    return textured_material(spec, "env_wall", _mottle(img, rng, 2.0), (0.5, 0.5), True)


def _add_lights(spec: mujoco.MjSpec, env: EnvironmentSpec, lighting: Lighting) -> None:
    """Key light (diffuse only, casts shadows) and a shadowless fill that carries the ambient.

    MuJoCo renders shadows in two passes: shadowless lights first, then each shadow-casting
    light added with its *whole* contribution masked by the shadow map. Keeping the ambient on
    the fill light keeps shadowed areas lit, and keeping the sum below 1 makes renders with
    and without shadows agree outside the shadows.
    """
    d = key_light_direction(env, lighting)
    key = KEY_GAIN * env.light.diffuse * lighting.intensity
    amb = env.light.ambient
    spec.worldbody.add_light(
        name=KEY_LIGHT,
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        pos=[-6.0 * d[0], -6.0 * d[1], -6.0 * d[2]],  # shadow map centred on the work area
        dir=list(d),
        diffuse=[key, key, key],
        ambient=[0.0, 0.0, 0.0],
        specular=[0.15, 0.15, 0.15],
        castshadow=True,
    )
    horiz = math.hypot(d[0], d[1]) or 1.0
    fill_dir = [-d[0] / horiz, -d[1] / horiz, -0.6]  # opposite the key, low: lights its far sides
    spec.worldbody.add_light(
        name=FILL_LIGHT,
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        pos=[-4.0 * fill_dir[0], -4.0 * fill_dir[1], 4.0],
        dir=fill_dir,
        diffuse=[FILL_DIFFUSE] * 3,
        ambient=[amb, amb, amb],
        specular=[0.0, 0.0, 0.0],
        castshadow=False,
    )


def _shade(rgba: RGBA, k: float) -> RGBA:
    return (rgba[0] * k, rgba[1] * k, rgba[2] * k, rgba[3])


def _yaw_quat(yaw_deg: float) -> list[float]:
    h = math.radians(yaw_deg) / 2
    return [math.cos(h), 0.0, 0.0, math.sin(h)]
