"""Materials and procedural textures for MjSpec scenes (deduplicated by name).

Gotcha (docs/design.md#simulator-notes): never pass ``textures=[...]`` to ``add_material`` and
then delete anything; set ``mat.textures[mjTEXROLE_RGB]`` instead.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.types.base import RGBA

TextureFn = Callable[[int, int], NDArray[np.uint8]]


def _exists(items: object, name: str) -> bool:
    return any(getattr(x, "name", None) == name for x in items)  # type: ignore[attr-defined]


def solid_material(
    spec: mujoco.MjSpec, name: str, rgba: RGBA, specular: float = 0.3, shininess: float = 0.3
) -> str:
    """Add (once) a plain coloured material; returns its name."""
    if not _exists(spec.materials, name):
        mat = spec.add_material(name=name)
        mat.rgba = list(rgba)
        mat.specular = specular
        mat.shininess = shininess
    return name


def image_texture(spec: mujoco.MjSpec, name: str, image: NDArray[np.uint8]) -> str:
    """Add (once) a 2-D RGB texture from an ``(H, W, 3)`` uint8 array; returns its name."""
    if not _exists(spec.textures, name):
        height, width, _ = image.shape
        tex = spec.add_texture(
            name=name, type=mujoco.mjtTexture.mjTEXTURE_2D, width=width, height=height, nchannel=3
        )
        tex.data = np.ascontiguousarray(image, dtype=np.uint8).tobytes()
    return name


def textured_material(
    spec: mujoco.MjSpec,
    name: str,
    image: NDArray[np.uint8],
    texrepeat: tuple[float, float] = (1.0, 1.0),
    texuniform: bool = False,
    rgba: RGBA = (1.0, 1.0, 1.0, 1.0),
    specular: float = 0.2,
) -> str:
    """Add (once) a material carrying an image texture; returns its name."""
    if not _exists(spec.materials, name):
        tex = image_texture(spec, f"{name}_tex", image)
        mat = spec.add_material(name=name)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex
        mat.texrepeat = list(texrepeat)
        mat.texuniform = texuniform
        mat.rgba = list(rgba)
        mat.specular = specular
    return name


def to_u8(rgba: RGBA) -> NDArray[np.uint8]:
    """RGB byte triple of a float colour."""
    return np.clip(np.asarray(rgba[:3]) * 255.0, 0, 255).astype(np.uint8)
