"""Planning: the scene the robot plans in, built from its percepts, and the plans. May use
Drake's MultibodyPlant queries, InverseKinematics and MathematicalProgram; no Drake systems with
ports."""
