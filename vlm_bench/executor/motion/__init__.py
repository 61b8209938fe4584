"""How the robot moves, independent of any skill.

``ik`` (the arm's inverse kinematics), ``collision_check`` (what a posture would touch),
``base_move`` (a UAV offset and heading turn), ``joint_moves`` (minimum-jerk servo moves),
``uav_moves`` (flights, turns, the stow), ``arm_core`` (one loop's arm: IK, collision queries
along paths, the held object), ``lines`` (straight TCP lines and glides), ``flight_clearance``
(carrying a held object clear on a flight), ``stow_clear`` (a stow clear of the scene) and
``arm_planner`` (choosing a clear reach among IK branches and UAV assists).
"""
