"""Franka Emika Panda arm with the Franka hand, built from primitive geoms with ``MjSpec``.

Kinematics follow Franka's published Craig (modified) DH parameters: each link body sits at
``RotX(alpha) · TransX(a) · TransZ(d)`` in its parent and turns about its local z axis. Masses,
centres of mass and (diagonal) inertias follow the identified values shipped with MuJoCo
Menagerie's Panda, except link 1, whose published 0.70 kg·m² transverse inertia is a known URDF
artefact; it uses a tenth of that. Geoms are white links with dark joint rings, like the real arm.

Actuation: position servos on the seven joints (Menagerie's gains and torque limits) and one
servo on the tendon that couples the two fingers; its control is the opening of *each* finger
in metres, ``0`` (closed) to :data:`GRIPPER_OPEN` (0.04, i.e. 8 cm between the pads). Gravity
is compensated per body (``gravcomp=1``) and routed through the joint actuators
(``actgravcomp``), so the compensation respects the torque limits. Note that MuJoCo applies the
free-joint part of that compensation to the floating base too; :class:`UavController` adds the
arm's weight back to the base so that the UAV carries it (see ``uav_control``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.sim import constants as c
from vlm_bench.sim.materials import solid_material
from vlm_bench.types.base import Vec3

Quat = tuple[float, float, float, float]

# Craig DH parameters of joints 1..7 (m, rad) and the flange offset along joint 7's axis.
DH_A = (0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088)
DH_D = (0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.0)
DH_ALPHA = (0.0, -math.pi / 2, math.pi / 2, math.pi / 2, -math.pi / 2, math.pi / 2, math.pi / 2)
FLANGE_D = 0.107
JOINT_LIMITS = (
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
)
# Servo stiffness (N·m/rad), damping (N·m·s/rad) and torque limit (N·m) per joint.
SERVO_KP = (4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0)
SERVO_KV = (450.0, 450.0, 350.0, 350.0, 200.0, 200.0, 200.0)
TORQUE_LIMIT = (87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0)
JOINT_ARMATURE = 0.1
JOINT_DAMPING = 1.0

# Hand: rotated -45° about the flange axis; fingers slide along the hand's ±y.
HAND_YAW = -math.pi / 4
FINGER_Z = 0.0584  # finger body origin along the hand's z (m)
PAD_Z = 0.041  # fingertip pad centre along the finger (m)
TCP_Z = FINGER_Z + PAD_Z  # TCP site along the hand's z: between the pad centres (m)
GRIPPER_KP = 2000.0  # N per m of finger-opening error, on the coupling tendon
GRIPPER_KV = 60.0
GRIPPER_FORCE = 140.0  # tendon force limit (N); each finger gets half
PAD_FRICTION = (1.6, 0.02, 0.002)
WRIST_CAMERA_TILT_DEG = 20.0  # towards the fingertips, from the gripper axis
WRIST_CAMERA_FOVY = 75.0


@dataclass(frozen=True)
class Inertial:
    """Mass (kg), centre of mass (m, body frame) and diagonal inertia (kg·m²) of a link."""

    mass: float
    com: Vec3
    inertia: Vec3


LINK_INERTIALS = (
    Inertial(0.629769, (-0.041018, -0.00014, 0.049974), (0.00315, 0.00388, 0.004285)),
    Inertial(4.970684, (0.003875, 0.002081, -0.04762), (0.070337, 0.070661, 0.009117)),
    Inertial(0.646926, (-0.003141, -0.02872, 0.003495), (0.007962, 0.02811, 0.025995)),
    Inertial(3.228604, (0.027518, 0.039252, -0.066502), (0.037242, 0.036155, 0.01083)),
    Inertial(3.587895, (-0.05317, 0.104419, 0.027454), (0.025853, 0.019552, 0.028323)),
    Inertial(1.225946, (-0.011953, 0.041065, -0.038437), (0.035549, 0.029474, 0.008627)),
    Inertial(1.666555, (0.060149, -0.014117, -0.010517), (0.001964, 0.004354, 0.005433)),
    Inertial(0.735522, (0.010517, -0.004252, 0.061597), (0.012516, 0.010027, 0.004815)),
)
HAND_INERTIAL = Inertial(0.73, (-0.01, 0.0, 0.03), (0.001, 0.0025, 0.0017))
FINGER_INERTIAL = Inertial(0.015, (0.0, 0.0075, 0.027), (2.375e-6, 2.375e-6, 7.5e-7))

WHITE = "panda_white"
DARK = "panda_dark"
BLACK = "panda_black"


def dh_link_pose(i: int) -> tuple[Vec3, Quat]:
    """Position and quaternion of link ``i + 1`` in link ``i``'s frame, from DH row ``i``."""
    a, d, alpha = DH_A[i], DH_D[i], DH_ALPHA[i]
    half = alpha / 2
    pos = (a, -math.sin(alpha) * d, math.cos(alpha) * d)
    return pos, (math.cos(half), math.sin(half), 0.0, 0.0)


def flange_transform(q: Sequence[float]) -> NDArray[np.float64]:
    """4×4 pose of the flange (link 8) in link 0's frame for joint angles ``q`` (rad)."""
    if len(q) != 7:
        raise ValueError(f"expected 7 joint angles, got {len(q)}")
    pose = np.eye(4)
    for i, theta in enumerate(q):
        ca, sa = math.cos(DH_ALPHA[i]), math.sin(DH_ALPHA[i])
        ct, st = math.cos(theta), math.sin(theta)
        step = np.array(
            [
                [ct, -st, 0.0, DH_A[i]],
                [st * ca, ct * ca, -sa, -sa * DH_D[i]],
                [st * sa, ct * sa, ca, ca * DH_D[i]],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
        pose = pose @ step
    flange = np.eye(4)
    flange[2, 3] = FLANGE_D
    return pose @ flange


def _set_inertial(body: mujoco.MjsBody, inertial: Inertial) -> None:
    body.explicitinertial = True
    body.mass = inertial.mass
    body.ipos = list(inertial.com)
    body.inertia = list(inertial.inertia)


# Link geometry in each link's own (DH) frame: (kind, from, to, radius). Kinds: "link" is a white
# capsule, "housing" a white joint cylinder with dark end rings, "band" a dark ring (visual only),
# "plate" a dark cylinder. All but bands collide.
Part = tuple[str, Vec3, Vec3, float]
LINK_PARTS: tuple[tuple[Part, ...], ...] = (
    (  # base: mounting plate and column up to joint 1
        ("plate", (0, 0, 0), (0, 0, 0.02), 0.075),
        ("link", (0, 0, 0.06), (0, 0, 0.13), 0.062),
        ("band", (0, 0, 0.135), (0, 0, 0.15), 0.058),
    ),
    (  # shoulder column; joint 2 turns about its +y
        ("link", (0, 0, -0.17), (0, 0, -0.03), 0.06),
        ("housing", (0, -0.066, 0), (0, 0.066, 0), 0.06),
    ),
    (("link", (0, 0, 0), (0, -0.19, 0), 0.056),),  # upper arm towards joint 3 at y = -0.316
    (  # end of the upper arm and the elbow offset to joint 4
        ("band", (0, 0, -0.13), (0, 0, -0.115), 0.054),
        ("link", (0, 0, -0.12), (0, 0, 0), 0.056),
        ("link", (0, 0, 0), (0.0825, 0, 0), 0.055),
    ),
    (  # elbow housing and the start of the forearm (towards +y, back on the axis at x = -0.0825)
        ("housing", (0, 0, -0.06), (0, 0, 0.06), 0.056),
        ("link", (0, 0, 0), (-0.0825, 0.12, 0), 0.052),
    ),
    (  # forearm along -z up to the wrist
        ("band", (0, 0, -0.265), (0, 0, -0.25), 0.05),
        ("link", (0, 0, -0.25), (0, 0, -0.06), 0.05),
    ),
    (  # wrist housing (joint 6) and the offset to joint 7
        ("housing", (0, 0, -0.06), (0, 0, 0.06), 0.052),
        ("link", (0.03, 0, 0), (0.088, 0, 0), 0.045),
    ),
    (  # link 7: short cylinder and the flange
        ("link", (0, 0, 0.045), (0, 0, 0.075), 0.045),
        ("band", (0, 0, 0.08), (0, 0, FLANGE_D), 0.04),
    ),
)


def _add_part(body: mujoco.MjsBody, part: Part) -> None:
    kind, p0, p1, radius = part
    geom = mujoco.mjtGeom.mjGEOM_CAPSULE if kind == "link" else mujoco.mjtGeom.mjGEOM_CYLINDER
    material = WHITE if kind in ("link", "housing") else DARK
    collide = 0 if kind == "band" else 1
    body.add_geom(
        type=geom, fromto=[*p0, *p1], size=[radius, 0, 0], material=material,
        contype=collide, conaffinity=collide,
    )  # fmt: skip
    if kind == "housing":  # dark caps just proud of both faces
        a, b = np.array(p0, dtype=float), np.array(p1, dtype=float)
        cap = 0.004 * (b - a) / np.linalg.norm(b - a)
        for end in (a, b):
            body.add_geom(
                type=geom, fromto=[*(end - cap), *(end + cap)], size=[0.8 * radius, 0, 0],
                material=DARK, contype=0, conaffinity=0,
            )  # fmt: skip


def _add_hand(spec: mujoco.MjSpec, link7: mujoco.MjsBody) -> None:
    half = HAND_YAW / 2
    hand = link7.add_body(
        name=c.HAND_BODY, pos=[0, 0, FLANGE_D], quat=[math.cos(half), 0, 0, math.sin(half)]
    )
    hand.gravcomp = 1.0
    _set_inertial(hand, HAND_INERTIAL)
    hand.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX,
        pos=[0, 0, 0.033],
        size=[0.026, 0.095, 0.024],
        material=WHITE,
    )
    hand.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX,
        pos=[0, 0, 0.0555],
        size=[0.018, 0.07, 0.003],
        material=DARK,
        contype=0,
        conaffinity=0,
    )
    # Wrist camera beside the hand, looking along the gripper, tilted towards the fingertips.
    hand.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX,
        pos=[0.036, 0, 0.03],
        size=[0.012, 0.03, 0.012],
        material=BLACK,
    )
    tilt = math.radians(WRIST_CAMERA_TILT_DEG)  # image right = hand +y, image up ≈ hand +x
    wrist = hand.add_camera(name=c.CAM_WRIST, pos=[0.05, 0, 0.035], fovy=WRIST_CAMERA_FOVY)
    wrist.alt.type = mujoco.mjtOrientation.mjORIENTATION_XYAXES
    wrist.alt.xyaxes = [0, 1, 0, math.cos(tilt), 0, math.sin(tilt)]
    hand.add_site(name=c.TCP_SITE, pos=[0, 0, TCP_Z], size=[0.006, 0, 0], rgba=[1, 0.2, 0.2, 0])
    for body_name, joint_name, yaw in (
        (c.LEFT_FINGER_BODY, c.FINGER_JOINTS[0], 0.0),
        (c.RIGHT_FINGER_BODY, c.FINGER_JOINTS[1], math.pi),
    ):
        finger = hand.add_body(
            name=body_name, pos=[0, 0, FINGER_Z], quat=[math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)]
        )
        finger.gravcomp = 1.0
        _set_inertial(finger, FINGER_INERTIAL)
        finger.add_joint(
            name=joint_name,
            type=mujoco.mjtJoint.mjJNT_SLIDE,
            axis=[0, 1, 0],
            range=[0, c.GRIPPER_OPEN],
            damping=2.0,
            armature=0.01,
            actgravcomp=True,
        )
        finger.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[0, 0.0085, 0.027],
            size=[0.0105, 0.005, 0.027],
            material=DARK,
        )
        finger.add_geom(
            name=f"{body_name}_pad",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[0, 0.002, PAD_Z],
            size=[0.0095, 0.0015, 0.013],
            material=BLACK,
            friction=list(PAD_FRICTION),
            condim=4,
            priority=1,
            solref=[0.005, 1.0],
            solimp=[0.95, 0.99, 0.001, 0.5, 2.0],
        )
    tendon = spec.add_tendon(name=f"{c.ARM_PREFIX}finger_split")
    for joint_name in c.FINGER_JOINTS:
        tendon.wrap_joint(joint_name, 0.5)
    spec.add_equality(
        type=mujoco.mjtEq.mjEQ_JOINT,
        name1=c.FINGER_JOINTS[0],
        name2=c.FINGER_JOINTS[1],
        solref=[0.005, 1.0],
        solimp=[0.95, 0.99, 0.001, 0.5, 2.0],
    )
    gripper = spec.add_actuator(
        name=c.GRIPPER_ACTUATOR,
        trntype=mujoco.mjtTrn.mjTRN_TENDON,
        target=tendon.name,
        ctrlrange=[0, c.GRIPPER_OPEN],
        forcerange=[-GRIPPER_FORCE, GRIPPER_FORCE],
    )
    gripper.set_to_position(kp=GRIPPER_KP, kv=GRIPPER_KV)


def _ensure_materials(spec: mujoco.MjSpec) -> None:
    solid_material(spec, WHITE, (0.93, 0.93, 0.92, 1.0), specular=0.5, shininess=0.4)
    solid_material(spec, DARK, (0.22, 0.22, 0.24, 1.0), specular=0.3, shininess=0.3)
    solid_material(spec, BLACK, (0.06, 0.06, 0.06, 1.0), specular=0.1, shininess=0.1)


def add_panda(spec: mujoco.MjSpec, parent: mujoco.MjsBody, pos: Vec3, quat: Quat) -> None:
    """Add the Panda (link 0 to the hand), its servos and finger coupling under ``parent``.

    Args:
        spec: Scene spec to add actuators, tendon and equality to.
        parent: Body that carries link 0 (the UAV chassis).
        pos: Link 0 origin in ``parent``'s frame (m).
        quat: Link 0 orientation in ``parent``'s frame (w, x, y, z).
    """
    _ensure_materials(spec)
    # Joint ranges are read in the spec's angle unit (MjSpec defaults to degrees).
    unit = 180.0 / math.pi if spec.compiler.degree else 1.0
    body = parent.add_body(name=c.ARM_LINKS[0], pos=list(pos), quat=list(quat))
    for i in range(8):
        if i > 0:
            link_pos, link_quat = dh_link_pose(i - 1)
            body = body.add_body(name=c.ARM_LINKS[i], pos=list(link_pos), quat=list(link_quat))
            lower, upper = JOINT_LIMITS[i - 1]
            body.add_joint(
                name=c.ARM_JOINTS[i - 1],
                type=mujoco.mjtJoint.mjJNT_HINGE,
                axis=[0, 0, 1],
                range=[lower * unit, upper * unit],
                armature=JOINT_ARMATURE,
                damping=JOINT_DAMPING,
                actgravcomp=True,
            )
        body.gravcomp = 1.0
        _set_inertial(body, LINK_INERTIALS[i])
        for part in LINK_PARTS[i]:
            _add_part(body, part)
    _add_hand(spec, body)
    for j in range(7):
        servo = spec.add_actuator(
            name=c.ARM_ACTUATORS[j],
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            target=c.ARM_JOINTS[j],
            ctrlrange=list(JOINT_LIMITS[j]),
            forcerange=[-TORQUE_LIMIT[j], TORQUE_LIMIT[j]],
        )
        servo.set_to_position(kp=SERVO_KP[j], kv=SERVO_KV[j])
    # Primitive hulls of links two apart overlap around the compact wrist and elbow.
    for i in range(len(c.ARM_LINKS) - 2):
        spec.add_exclude(bodyname1=c.ARM_LINKS[i], bodyname2=c.ARM_LINKS[i + 2])
    for link in c.ARM_LINKS[5:7]:
        spec.add_exclude(bodyname1=link, bodyname2=c.HAND_BODY)
