"""Quad-X airframe built from primitives: a floating body (free joint) with cameras and rotors.

About 1 m across from rotor tip to rotor tip: four 0.33 m arms at ±45°/±135° carry motor pods and
0.17 m rotor discs. The rotor discs collide (contype/conaffinity 1), so the airframe meets
furniture physically; the blades drawn on them are visual only. Body +x is the front, marked by
an orange arrow lying on top of the chassis (and two green lights; a red one at the back); +z is
up. The ``uav`` camera sits at the front of the chassis, looking forward and 35° down. The body
carries an explicit inertial (mass :data:`UAV_MASS`), not one from geoms, so visual geoms
change nothing physical.
"""

from __future__ import annotations

import math

import mujoco

from vlm_bench.sim import constants as c
from vlm_bench.sim.materials import solid_material
from vlm_bench.types.episode import UavPose
from vlm_bench.types.geometry import UAV_ARM_LENGTH, UAV_ROTOR_RADIUS

UAV_MASS = 8.0  # airframe, motors and battery (kg)
UAV_INERTIA = (0.30, 0.30, 0.52)  # diagonal (kg·m²), body frame
ARM_LENGTH = UAV_ARM_LENGTH  # chassis centre to motor axis (m)
ROTOR_RADIUS = UAV_ROTOR_RADIUS
ROTOR_Z = 0.065  # rotor disc height above the body origin (m)
CAMERA_PITCH_DEG = 35.0
CAMERA_FOVY = 75.0
CAMERA_POS = (0.17, 0.0, -0.005)
MOUNT_BOTTOM = -0.095  # lower face of the arm mount under the chassis (m)

FRAME = "uav_frame"
SHELL = "uav_shell"
METAL = "uav_metal"
PROP = "uav_prop"
PROP_DISC = "uav_prop_disc"
HEADING = "uav_heading"

# Heading arrow: a flat orange arrow lying on top of the chassis along body +x, self-lit so it
# reads under any lighting. Body-frame coordinates (m); it stays above the `uav` camera's view.
HEADING_RGBA = (1.0, 0.45, 0.0, 1.0)  # orange, as rendered
# MuJoCo shades a material as rgba * (emission + light), clipped at 1: a dim base colour with a
# strong emission keeps the hue from lit top faces (light up to ~1.05) to shadows (~0.1).
HEADING_EMISSION = 1.9
HEADING_MAX_LIGHT = 1.05
HEADING_Z = c.UAV_HEADING_Z
HEADING_HALF_THICKNESS = 0.006
HEADING_TAIL_X = c.UAV_HEADING_TAIL_X
HEADING_NECK_X = 0.30  # where the shaft meets the head
HEADING_TIP_X = c.UAV_HEADING_TIP_X
HEADING_SHAFT_HALF_WIDTH = 0.04
HEADING_HEAD_HALF_WIDTH = 0.13


def yaw_quat(yaw_deg: float) -> list[float]:
    """Quaternion (w, x, y, z) of a heading ``yaw_deg`` about world z."""
    half = math.radians(yaw_deg) / 2
    return [math.cos(half), 0.0, 0.0, math.sin(half)]


def _ensure_materials(spec: mujoco.MjSpec) -> None:
    solid_material(spec, FRAME, (0.10, 0.10, 0.11, 1.0), specular=0.4, shininess=0.5)
    solid_material(spec, SHELL, (0.28, 0.29, 0.31, 1.0), specular=0.5, shininess=0.6)
    solid_material(spec, METAL, (0.55, 0.56, 0.58, 1.0), specular=0.8, shininess=0.8)
    solid_material(spec, PROP, (0.03, 0.03, 0.03, 1.0), specular=0.2, shininess=0.3)
    solid_material(spec, PROP_DISC, (0.05, 0.05, 0.05, 0.28), specular=0.1, shininess=0.1)
    gain = 1.0 / (HEADING_EMISSION + HEADING_MAX_LIGHT)
    base = (HEADING_RGBA[0] * gain, HEADING_RGBA[1] * gain, HEADING_RGBA[2] * gain, 1.0)
    solid_material(spec, HEADING, base, specular=0.0, shininess=0.0)
    spec.material(HEADING).emission = HEADING_EMISSION


def _visual(body: mujoco.MjsBody, **kwargs: object) -> None:
    body.add_geom(contype=0, conaffinity=0, **kwargs)


def _add_chassis(body: mujoco.MjsBody) -> None:
    box, cyl = mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_CYLINDER
    body.add_geom(type=box, pos=[0, 0, -0.03], size=[0.16, 0.12, 0.008], material=FRAME)
    body.add_geom(type=box, pos=[0, 0, 0.0], size=[0.13, 0.09, 0.03], material=SHELL)
    body.add_geom(
        type=mujoco.mjtGeom.mjGEOM_ELLIPSOID,
        pos=[0.01, 0, 0.03],
        size=[0.12, 0.085, 0.04],
        material=SHELL,
    )
    body.add_geom(type=box, pos=[-0.01, 0, 0.08], size=[0.09, 0.05, 0.022], material=FRAME)
    _visual(body, type=box, pos=[-0.01, 0, 0.103], size=[0.06, 0.03, 0.002], rgba=[0.9, 0.7, 0, 1])
    _visual(
        body, type=cyl, fromto=[-0.08, 0, 0.1, -0.08, 0, 0.15], size=[0.005, 0, 0], material=METAL
    )
    _visual(
        body, type=cyl, fromto=[-0.08, 0, 0.15, -0.08, 0, 0.158], size=[0.03, 0, 0], material=SHELL
    )
    _visual(
        body,
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        pos=[0.163, 0.05, 0.0],
        size=[0.012, 0, 0],
        rgba=[0.1, 1, 0.2, 1],
    )
    _visual(
        body,
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        pos=[0.163, -0.05, 0.0],
        size=[0.012, 0, 0],
        rgba=[0.1, 1, 0.2, 1],
    )
    _visual(
        body,
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        pos=[-0.163, 0, 0.0],
        size=[0.012, 0, 0],
        rgba=[1, 0.1, 0.1, 1],
    )
    # Camera housing and the arm mount under the chassis.
    body.add_geom(type=box, pos=[0.15, 0, -0.005], size=[0.02, 0.025, 0.02], material=FRAME)
    body.add_geom(
        type=cyl, fromto=[0, 0, -0.035, 0, 0, MOUNT_BOTTOM], size=[0.05, 0, 0], material=FRAME
    )


def _add_heading_arrow(spec: mujoco.MjSpec, body: mujoco.MjsBody) -> None:
    """Shaft (a flat box) and head (a flat triangular prism) pointing along body +x."""
    z, half = HEADING_Z, HEADING_HALF_THICKNESS
    _visual(
        body,
        name=c.UAV_HEADING_SHAFT,
        type=mujoco.mjtGeom.mjGEOM_BOX,
        pos=[(HEADING_TAIL_X + HEADING_NECK_X) / 2, 0.0, z],
        size=[(HEADING_NECK_X - HEADING_TAIL_X) / 2, HEADING_SHAFT_HALF_WIDTH, half],
        material=HEADING,
    )
    neck, tip, width = HEADING_NECK_X, HEADING_TIP_X, HEADING_HEAD_HALF_WIDTH
    corners = [(neck, width), (neck, -width), (tip, 0.0)]
    vertices = [v for x, y in corners for dz in (-half, half) for v in (x, y, z + dz)]
    if not any(m.name == c.UAV_HEADING_HEAD for m in spec.meshes):
        spec.add_mesh(name=c.UAV_HEADING_HEAD, uservert=vertices)
    _visual(
        body,
        name=c.UAV_HEADING_HEAD,
        type=mujoco.mjtGeom.mjGEOM_MESH,
        meshname=c.UAV_HEADING_HEAD,
        material=HEADING,
    )


def _add_rotor_arms(body: mujoco.MjsBody) -> None:
    cyl = mujoco.mjtGeom.mjGEOM_CYLINDER
    for k in range(4):
        angle = math.radians(45.0 + 90.0 * k)
        x, y = ARM_LENGTH * math.cos(angle), ARM_LENGTH * math.sin(angle)
        body.add_geom(
            type=mujoco.mjtGeom.mjGEOM_CAPSULE,
            fromto=[0.08 * x / ARM_LENGTH, 0.08 * y / ARM_LENGTH, 0, x, y, 0.005],
            size=[0.016, 0, 0],
            material=FRAME,
        )
        body.add_geom(type=cyl, pos=[x, y, 0.015], size=[0.032, 0.03, 0], material=METAL)
        _visual(body, type=cyl, pos=[x, y, 0.05], size=[0.012, 0.006, 0], material=FRAME)
        body.add_geom(
            name=f"{c.ROTOR_GEOM_PREFIX}{k}",
            type=cyl,
            pos=[x, y, ROTOR_Z],
            size=[ROTOR_RADIUS, 0.003, 0],
            material=PROP_DISC,
        )
        blade_yaw = angle + math.radians(30.0 * (1 if k % 2 else -1))
        half = blade_yaw / 2
        _visual(
            body,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[x, y, ROTOR_Z + 0.004],
            quat=[math.cos(half), 0, 0, math.sin(half)],
            size=[ROTOR_RADIUS - 0.005, 0.013, 0.002],
            material=PROP,
        )


def add_uav(spec: mujoco.MjSpec, start: UavPose) -> mujoco.MjsBody:
    """Add the floating UAV body at ``start`` to ``spec.worldbody`` and return it.

    Args:
        spec: Scene spec.
        start: Initial body position (m) and heading (deg, CCW from world +x).

    Returns:
        The UAV body, for mounting the arm under it.
    """
    _ensure_materials(spec)
    body = spec.worldbody.add_body(
        name=c.UAV_BODY, pos=list(start.pos), quat=yaw_quat(start.yaw_deg)
    )
    body.add_freejoint(name=c.UAV_FREEJOINT)
    body.explicitinertial = True
    body.mass = UAV_MASS
    body.ipos = [0.0, 0.0, 0.0]
    body.inertia = list(UAV_INERTIA)
    _add_chassis(body)
    _add_rotor_arms(body)
    _add_heading_arrow(spec, body)
    body.add_site(name=c.UAV_SITE, pos=[0, 0, 0], size=[0.01, 0, 0], rgba=[1, 1, 0, 0])
    pitch = math.radians(CAMERA_PITCH_DEG)  # image right = body -y, image up tilted forward
    camera = body.add_camera(name=c.CAM_UAV, pos=list(CAMERA_POS), fovy=CAMERA_FOVY)
    camera.alt.type = mujoco.mjtOrientation.mjORIENTATION_XYAXES
    camera.alt.xyaxes = [0, -1, 0, math.sin(pitch), 0, math.cos(pitch)]
    return body
