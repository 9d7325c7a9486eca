"""The topics, frames and joint names of a Toyota HSR's ROS bag, as the robot publishes them, and
the names this project gives what the HSR has no topic for (skeletons, the robot's settings).

A bag is read and written with these names by default (`BagTopics`); each can be changed on the
command line for a bag recorded under other names.
"""

from __future__ import annotations

import dataclasses

from hsr_handover.interface.joint_trajectory import ARM_CONTROLLER, BASE_CONTROLLER, CONTROLLERS

COLOR_TOPIC = "/hsrb/head_rgbd_sensor/rgb/image_rect_color"
COMPRESSED_SUFFIX = "/compressed"
"""image_transport's compressed twin of an image topic (sensor_msgs/CompressedImage)."""
DEPTH_TOPIC = "/hsrb/head_rgbd_sensor/depth_registered/image_rect_raw"
CAMERA_INFO_TOPIC = "/hsrb/head_rgbd_sensor/rgb/camera_info"
JOINT_STATES_TOPIC = "/hsrb/joint_states"
TF_TOPIC = "/tf"
TF_STATIC_TOPIC = "/tf_static"
SKELETON_TOPIC = "/openpose/pose_keypoints"
"""geometry_msgs/PolygonStamped, one per colour image (its stamp): each person's keypoints in
OpenPose's order, one after another, as points (x = u px, y = v px, z = confidence); ROS has no
standard message for 2-D body keypoints, and this one every ROS tool reads."""
SETTINGS_TOPIC = "/hsr_handover/session_settings"
"""std_msgs/String: the robot's perception settings as a session.yaml holds them (written once)."""

ARM_TRAJECTORY_TOPIC = ARM_CONTROLLER
BASE_TRAJECTORY_TOPIC = BASE_CONTROLLER

ODOM_FRAME = "odom"
BASE_FRAME = "base_footprint"
CAMERA_LINK_FRAME = "head_rgbd_sensor_link"
"""The head camera's body frame (x forward, y left, z up, as ROS bodies are)."""
CAMERA_FRAME = "head_rgbd_sensor_rgb_frame"
"""The head camera's optical frame (z forward, x right, y down), the images' frame_id."""

HSR_JOINT_NAMES = CONTROLLERS[BASE_CONTROLLER]
"""The model's base joints by the names the HSR's omni base gives them; every other joint of
`hsr.COMMANDED_JOINTS` has the HSR's own name already."""


def hsr_joint_name(model_joint: str) -> str:
    """The HSR's name of one of the model's joints (`HSR_JOINT_NAMES`, else the same)."""
    return HSR_JOINT_NAMES.get(model_joint, model_joint)


@dataclasses.dataclass(frozen=True)
class BagTopics:
    """Where a bag holds each stream. `base_frame` None: `odom`, else `base_footprint` when the
    bag's TF has no `odom`."""

    color: str = COLOR_TOPIC
    depth: str = DEPTH_TOPIC
    camera_info: str = CAMERA_INFO_TOPIC
    joint_states: str = JOINT_STATES_TOPIC
    skeleton: str = SKELETON_TOPIC
    base_frame: str | None = None
    camera_frame: str = CAMERA_FRAME


HSR_TOPICS = BagTopics()
"""The HSR's own names."""
