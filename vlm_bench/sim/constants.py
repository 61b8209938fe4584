"""Every MJCF name the simulator, executor and tests refer to, in one place."""

from __future__ import annotations

# Timing (docs/design.md#executor): physics at 400 Hz, the UAV controller at 200 Hz, control
# at 20 Hz.
PHYSICS_DT = 0.0025
"""s: the physics step, the largest that keeps every contact as stiff as specified: MuJoCo
clamps a contact's time constant to at least two steps, and the finger pads' is 5 ms
(``sim/panda.py``). At 3.125 ms the pads soften and a held cup slips out
(docs/decisions.md, "Simulation speed")."""
SLEEP = True
"""MuJoCo's sleeping islands: bodies at rest (objects on tables) stop being simulated until
something touches them, ~2-3x fewer contacts and a faster step (the robot, actuated, stays
awake). Validated by the oracle sweep (see docs/performance.md)."""
CONTROL_DT = 0.05
STEPS_PER_CONTROL = round(CONTROL_DT / PHYSICS_DT)
UAV_CONTROL_EVERY = 2
"""Physics steps per update of the UAV controller (200 Hz; its force is held in between).
At 100 Hz a push fell short (docs/decisions.md, "Simulation speed")."""

# UAV.
UAV_BODY = "uav"
UAV_FREEJOINT = "uav_free"
UAV_SITE = "uav_center"
ROTOR_GEOM_PREFIX = "uav_rotor"
# Orange arrow on top of the UAV pointing to its front (body +x); visual only.
UAV_HEADING_SHAFT = "uav_heading_shaft"
UAV_HEADING_HEAD = "uav_heading_head"
UAV_HEADING_GEOMS = (UAV_HEADING_SHAFT, UAV_HEADING_HEAD)
UAV_HEADING_Z = 0.112  # m above the UAV's origin: the arrow's mid-plane, just above the top plate
UAV_HEADING_TAIL_X = -0.04  # m along body +x: the arrow's tail, just ahead of the mast
UAV_HEADING_TIP_X = 0.52  # m along body +x: its tip, a little beyond the rotor tips

# Panda arm (mounted under the UAV, base pointing down).
ARM_PREFIX = "panda_"
ARM_BASE_BODY = "panda_link0"
ARM_LINKS = tuple(f"panda_link{i}" for i in range(8))
HAND_BODY = "panda_hand"
LEFT_FINGER_BODY = "panda_left_finger"
RIGHT_FINGER_BODY = "panda_right_finger"
ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
ARM_ACTUATORS = tuple(f"panda_actuator{i}" for i in range(1, 8))
GRIPPER_ACTUATOR = "panda_gripper"
TCP_SITE = "panda_tcp"
GRIPPER_OPEN = 0.04  # finger joint position (m) per finger when fully open
ARM_HOME = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)  # Panda "ready" pose (rad)
# Compact, contact-free flight pose of the hanging arm: folded back and up beside the mount,
# clear of the `uav` camera; lowest point is the shoulder (0.49 m below the UAV origin).
ARM_STOW = (0.0, -1.71, 2.53, -2.18, 0.0, 0.37, 0.0)
GRIPPER_CLOSED = 0.0  # finger joint position (m) when fully closed
# Start-of-episode pose for snapshots: the wrist camera 0.34 m below the UAV origin, looking
# forward and ~31° down; no arm link appears in the `uav` camera's image and nothing touches.
ARM_OBSERVE = (1.4484, 0.3484, 2.6925, -3.0662, 1.0110, 1.2698, 1.1909)

# Cameras (stable names, docs/design.md#world).
CAM_UAV = "uav"
CAM_WRIST = "wrist"
CAM_OVERHEAD = "overhead"
CAM_SIDE = "side"
CAMERAS = (CAM_UAV, CAM_WRIST, CAM_OVERHEAD, CAM_SIDE)
THIRD_PERSON_CAMERAS = (CAM_OVERHEAD, CAM_SIDE)
DEFAULT_IMAGE_SIZE = 448

# Objects: body name = object id; parts below.
FLOOR_GEOM = "floor"


def part_joint(part: str) -> str:
    """Joint of an articulated part (drawer slide or knob hinge)."""
    return f"{part}_joint"


def part_handle_site(part: str) -> str:
    """Site at the grasp point of a part's handle or knob."""
    return f"{part}_handle"


def object_geom(obj_id: str, piece: str) -> str:
    """Geom names are prefixed by their object id so contacts map back to objects."""
    return f"{obj_id}/{piece}"
