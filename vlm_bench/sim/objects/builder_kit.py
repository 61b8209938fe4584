"""The object-builder registry and the small toolkit every builder uses.

Conventions every builder follows (the simulator, executor and ground truth rely on them):
the object body is named after the object id and has its origin at the bottom centre of the
kind's bounding box, +x being the object's front; geoms are named ``object_geom(id, piece)``;
movable kinds get a free joint; the solid geoms share ``kind.mass`` in proportion to volume.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import mujoco

from vlm_bench.registry import Registry
from vlm_bench.sim.constants import object_geom
from vlm_bench.sim.materials import solid_material
from vlm_bench.sim.objects.frames import IDENTITY, Quat, segment, yaw
from vlm_bench.types.base import RGBA, Vec3
from vlm_bench.types.episode import EpisodeObject
from vlm_bench.types.world import ObjectKind

Look = str | RGBA  # a material name, or a plain colour turned into a matte material
VISUAL_GROUP = 1  # decoration geoms (labels, stickers): drawn, never collide, no mass
# Collision-only stand-ins under a detailed visual mesh; mjvOption hides group 3 by default.
COLLISION_GROUP = 3
_GEOM = mujoco.mjtGeom


class ObjectBuilder(Protocol):
    """Builds one object kind under ``parent`` and returns the object's body."""

    def __call__(
        self,
        spec: mujoco.MjSpec,
        parent: mujoco.MjsBody,
        obj: EpisodeObject,
        kind: ObjectKind,
        rgba: RGBA,
    ) -> mujoco.MjsBody: ...


OBJECT_BUILDERS: Registry[ObjectBuilder] = Registry("object builder")


@dataclass(frozen=True)
class Surface:
    """Contact properties of an object's solid geoms."""

    friction: Vec3
    condim: int


# Graspable things: high sliding friction and torsional friction (condim 4) for stable grasps.
GRIP = Surface(friction=(1.2, 0.01, 0.0002), condim=4)
PLAIN = Surface(friction=(1.0, 0.005, 0.0001), condim=3)


def free_joint_name(obj_id: str) -> str:
    """Name of the free joint of a movable object."""
    return f"{obj_id}/free"


def shade(rgba: RGBA, factor: float) -> RGBA:
    """The colour with its RGB scaled by ``factor`` (darker below 1), clipped to [0, 1]."""
    r, g, b, a = rgba
    return (min(r * factor, 1.0), min(g * factor, 1.0), min(b * factor, 1.0), a)


def mix(a: RGBA, b: RGBA, t: float) -> RGBA:
    """Linear blend from ``a`` (t=0) to ``b`` (t=1)."""
    return (
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
        a[3] + (b[3] - a[3]) * t,
    )


def is_light(rgba: RGBA) -> bool:
    """Whether a colour is light enough that dark details contrast with it better."""
    return 0.299 * rgba[0] + 0.587 * rgba[1] + 0.114 * rgba[2] > 0.6


def object_body(parent: mujoco.MjsBody, obj: EpisodeObject, kind: ObjectKind) -> mujoco.MjsBody:
    """The object's body at ``obj.pos`` turned ``obj.yaw_deg`` about z; free if movable."""
    body = parent.add_body(name=obj.id, pos=list(obj.pos), quat=list(yaw(obj.yaw_deg)))
    if kind.movable:
        body.add_freejoint(name=free_joint_name(obj.id))
    return body


def object_kit(
    spec: mujoco.MjSpec,
    parent: mujoco.MjsBody,
    obj: EpisodeObject,
    kind: ObjectKind,
    surface: Surface,
) -> Kit:
    """A :class:`Kit` on the object's new body (:func:`object_body`): every builder's opening."""
    return Kit(spec, object_body(parent, obj, kind), obj.id, surface)


def paint(spec: mujoco.MjSpec, rgba: RGBA, specular: float = 0.15, shininess: float = 0.2) -> str:
    """A shared plain material of one colour and finish; returns its name."""
    key = "_".join(f"{c:.3f}" for c in (*rgba, specular, shininess))
    return solid_material(spec, f"paint_{key}", rgba, specular=specular, shininess=shininess)


def _volume(gtype: mujoco.mjtGeom, size: Sequence[float]) -> float:
    if gtype == _GEOM.mjGEOM_BOX:
        return 8.0 * size[0] * size[1] * size[2]
    if gtype == _GEOM.mjGEOM_SPHERE:
        return 4.0 / 3.0 * math.pi * size[0] ** 3
    if gtype == _GEOM.mjGEOM_CYLINDER:
        return math.pi * size[0] ** 2 * 2.0 * size[1]
    if gtype == _GEOM.mjGEOM_CAPSULE:
        return math.pi * size[0] ** 2 * (2.0 * size[1] + 4.0 / 3.0 * size[0])
    if gtype == _GEOM.mjGEOM_ELLIPSOID:
        return 4.0 / 3.0 * math.pi * size[0] * size[1] * size[2]
    raise ValueError(f"no volume formula for geom type {gtype}")


class Kit:
    """Adds named geoms to one object body and shares the body's mass among its solid geoms.

    Solid geoms collide and carry mass in proportion to volume times ``density`` (relative);
    decoration geoms (``solid=False``) are drawn only: no contacts, no mass.
    """

    def __init__(
        self, spec: mujoco.MjSpec, body: mujoco.MjsBody, obj_id: str, surface: Surface
    ) -> None:
        self.spec, self.body, self.obj_id, self.surface = spec, body, obj_id, surface
        self._solids: list[tuple[mujoco.MjsGeom, float]] = []

    def look(self, look: Look) -> str:
        """Material name for ``look`` (a plain colour becomes a matte material)."""
        return look if isinstance(look, str) else paint(self.spec, look)

    def geom(
        self,
        piece: str,
        gtype: mujoco.mjtGeom,
        size: Sequence[float],
        pos: Vec3,
        look: Look,
        quat: Quat = IDENTITY,
        *,
        solid: bool = True,
        density: float = 1.0,
        volume: float | None = None,
    ) -> mujoco.MjsGeom:
        """Add one geom; ``volume`` overrides the primitive's formula (meshes need it)."""
        g = self.body.add_geom(
            name=object_geom(self.obj_id, piece),
            type=gtype,
            size=[*size, 0.0, 0.0, 0.0][:3],
            pos=list(pos),
            quat=list(quat),
            material=self.look(look),
        )
        if solid:
            g.friction = list(self.surface.friction)
            g.condim = self.surface.condim
            vol = _volume(gtype, size) if volume is None else volume
            self._solids.append((g, vol * density))
        else:
            g.contype, g.conaffinity, g.group, g.mass = 0, 0, VISUAL_GROUP, 0.0
        return g

    def box(
        self,
        piece: str,
        half: Vec3,
        pos: Vec3,
        look: Look,
        quat: Quat = IDENTITY,
        *,
        solid: bool = True,
        density: float = 1.0,
    ) -> mujoco.MjsGeom:
        """A box with half-extents ``half`` centred at ``pos``."""
        return self.geom(
            piece, _GEOM.mjGEOM_BOX, half, pos, look, quat, solid=solid, density=density
        )

    def cylinder(
        self,
        piece: str,
        radius: float,
        half_height: float,
        pos: Vec3,
        look: Look,
        quat: Quat = IDENTITY,
        *,
        solid: bool = True,
        density: float = 1.0,
    ) -> mujoco.MjsGeom:
        """A cylinder along the local z axis (turn it with ``quat``)."""
        size = (radius, half_height)
        return self.geom(
            piece, _GEOM.mjGEOM_CYLINDER, size, pos, look, quat, solid=solid, density=density
        )

    def sphere(
        self, piece: str, radius: float, pos: Vec3, look: Look, *, solid: bool = True
    ) -> mujoco.MjsGeom:
        """A sphere."""
        return self.geom(piece, _GEOM.mjGEOM_SPHERE, (radius,), pos, look, solid=solid)

    def ellipsoid(
        self,
        piece: str,
        radii: Vec3,
        pos: Vec3,
        look: Look,
        quat: Quat = IDENTITY,
        *,
        solid: bool = True,
    ) -> mujoco.MjsGeom:
        """An ellipsoid with semi-axes ``radii``."""
        return self.geom(piece, _GEOM.mjGEOM_ELLIPSOID, radii, pos, look, quat, solid=solid)

    def rod(
        self,
        piece: str,
        a: Vec3,
        b: Vec3,
        radius: float,
        look: Look,
        *,
        capped: bool = True,
        solid: bool = True,
    ) -> mujoco.MjsGeom:
        """A capsule (``capped``) or cylinder whose axis runs from ``a`` to ``b``."""
        centre, quat, half = segment(a, b)
        gtype = _GEOM.mjGEOM_CAPSULE if capped else _GEOM.mjGEOM_CYLINDER
        return self.geom(piece, gtype, (radius, half), centre, look, quat, solid=solid)

    def mesh(
        self,
        piece: str,
        vertices: Sequence[float],
        volume: float,
        look: Look,
        faces: Sequence[int] = (),
        *,
        solid: bool = True,
    ) -> mujoco.MjsGeom:
        """A mesh from flat ``vertices`` (body frame) and optional triangle ``faces``.

        Without faces the mesh is the vertices' convex hull; with faces it is drawn as given
        (holes and all) while its convex hull is what collides.
        """
        name = object_geom(self.obj_id, piece)
        mesh = self.spec.add_mesh(name=name, uservert=list(vertices))
        if faces:
            mesh.userface = list(faces)
        g = self.geom(
            piece, _GEOM.mjGEOM_MESH, (), (0.0, 0.0, 0.0), look, solid=solid, volume=volume
        )
        g.meshname = name
        return g

    def hide(self, geom: mujoco.MjsGeom) -> mujoco.MjsGeom:
        """Make a solid geom collision-only (not drawn by default): a visual mesh shows instead.

        Used where mesh contacts would jitter (mesh-on-plane picks changing contact vertices).
        """
        geom.group = COLLISION_GROUP
        return geom

    def finish(self, mass: float) -> mujoco.MjsBody:
        """Give the solid geoms ``mass`` in total, shared by weighted volume; returns the body."""
        total = sum(w for _, w in self._solids)
        for g, w in self._solids:
            g.mass = mass * w / total

        return self.body
