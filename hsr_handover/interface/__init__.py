"""The ports between the station (the world) and the robot: one name each, on both sides.

The robot's diagram names its inputs after the station's sensor outputs and its outputs after
the station's command inputs, so the two connect by name (`simulation.connect_robot`). Ports
named `truth_*` carry the simulator's ground truth, for scoring and for the simulated person
only; no robot system may read one.
"""

from __future__ import annotations

HSR_DESIRED_STATE = "hsr_desired_state"
"""[q_d; v_d] of `hsr.COMMANDED_JOINTS` (base, arm, head), in that order."""
GRIPPER_DESIRED_OPENING = "gripper_desired_opening"
"""[opening]: the desired distance between the fingertips (m)."""
COMMANDS = (HSR_DESIRED_STATE, GRIPPER_DESIRED_OPENING)

HSR_STATE_MEASURED = "hsr_state_measured"
"""[q; v] of `hsr.COMMANDED_JOINTS` as the joint encoders (and the base's odometry) read them."""
GRIPPER_OPENING_MEASURED = "gripper_opening_measured"
"""[opening]: the measured distance between the fingertips (m)."""
HSR_WRIST_WRENCH_MEASURED = "hsr_wrist_wrench_measured"
"""[torque; force] (N m, N) the hand, with what it holds, exerts on the wrist's force-torque
sensor, in the hand's frame (`hsr.PALM_FRAME`)."""
CAMERA_COLOR_IMAGE = "camera_color_image"
CAMERA_DEPTH_IMAGE = "camera_depth_image"
CAMERA_POSE = "camera_pose"
"""RigidTransform X_WC of the head camera at its last capture (z forward, x right, y down)."""
CAMERA_INFO = "camera_info"
"""The head camera's intrinsics (Drake CameraInfo)."""
CAMERA_IMAGE_TIME = "camera_image_time"
"""The time (s) the held images were captured."""
SKELETON_KEYPOINTS = "skeleton_keypoints"
"""The pose detector's 2-D COCO-18 keypoints of the last capture (interface.keypoints.Detection)."""
SENSORS = (
    HSR_STATE_MEASURED, GRIPPER_OPENING_MEASURED, HSR_WRIST_WRENCH_MEASURED, CAMERA_COLOR_IMAGE,
    CAMERA_DEPTH_IMAGE, CAMERA_POSE, CAMERA_INFO, CAMERA_IMAGE_TIME, SKELETON_KEYPOINTS,
)  # fmt: skip

COMMANDED_TRAJECTORIES = "commanded_trajectories"
"""The robot's motions started so far (tuple of `interface.joint_trajectory.JointTrajectory`): for
recording, never for the station, which takes `hsr_desired_state`."""

TRUTH_PREFIX = "truth_"
TRUTH_BODY_POSES = "truth_body_poses"
TRUTH_CONTACT_RESULTS = "truth_contact_results"
TRUTH_PERSON_STATE = "truth_person_state"
TRUTH_HSR_STATE = "truth_hsr_state"
TRUTH_QUERY_OBJECT = "truth_query_object"
TRUTH_LABEL_IMAGE = "truth_label_image"
"""The head camera's label image: which body each pixel shows, for scoring perception."""
TRUTH_PERSON_GRIP = "truth_person_grip"
"""The object the simulated person's hand holds ("" for none), for scoring a handover."""
TRUTH_PERSON_REPEATED_AT = "truth_person_repeated_at"
"""[t]: when the simulated person asked again for want of a response (s; NaN if they did not)."""
TRUTH = (
    TRUTH_BODY_POSES, TRUTH_CONTACT_RESULTS, TRUTH_PERSON_STATE, TRUTH_HSR_STATE,
    TRUTH_QUERY_OBJECT, TRUTH_LABEL_IMAGE, TRUTH_PERSON_GRIP, TRUTH_PERSON_REPEATED_AT,
)  # fmt: skip
