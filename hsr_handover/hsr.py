"""Plant-level helpers for the HSR-B model in models/hsrb/hsrb.sdf.

The model's actuated joints are PD-controlled (drake:controller_gains), so the robot is driven
through ``plant.get_desired_state_input_port(instance)``. Two joints are not actuated but coupled
by drake:mimic: torso_lift_joint = 0.5 x arm_lift_joint and hand_r_finger_joint =
hand_l_finger_joint. The coupling holds only in a discrete plant with a SAP-family contact
approximation (the default); IK and trajectory optimisation must add it themselves.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from pathlib import Path

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import Context

from hsr_handover.kinematics.hsr_arm import ARM_JOINT_NAMES
from hsr_handover.model_files import MODELS_DIR

PACKAGE_XML = MODELS_DIR / "package.xml"
PACKAGE_NAME = "hsr_handover"
HSR_URL = f"package://{PACKAGE_NAME}/hsrb/hsrb.sdf"

PALM_FRAME = "hand_palm_link"
WRIST_SENSOR_JOINT = "hand_palm_joint"
"""The fixed joint mounting the hand on the wrist, where the HSR's force-torque sensor sits; its
child frame is PALM_FRAME."""
CAMERA_FRAME = "head_rgbd_sensor_frame"
BASE_RADIUS = 0.218
"""m: the HSR's base disc (hsrb.sdf: round the base's x, y, 1 to 14 cm up)."""
BASE_JOINTS = ("base_x_joint", "base_y_joint", "base_yaw_joint")
ARM_JOINTS = ARM_JOINT_NAMES
HEAD_JOINTS = ("head_pan_joint", "head_tilt_joint")
COMMANDED_JOINTS = (*BASE_JOINTS, *ARM_JOINTS, *HEAD_JOINTS)
"""The joints the robot commands by position and velocity (the gripper is commanded apart)."""
TORSO_JOINT = "torso_lift_joint"
TORSO_PER_LIFT = 0.5  # the torso's lift per metre of the arm's (a mimic joint)
GRIPPER_JOINT = "hand_l_finger_joint"
GRIPPER_MIMIC_JOINT = "hand_r_finger_joint"
GRIPPER_KEY = "gripper"
GRIPPER_MAX_OPENING = 0.137
"""Largest distance between the fingertips (m)."""
FINGER_PER_OPENING = 0.5
"""Each finger travels half the opening between the fingertips."""
GRIPPER_CAPSULES = {
    "hand_l_finger_link": ((0.0, 0.01, 0.02), (0.0, 0.01, 0.08), 0.01),
    "hand_r_finger_link": ((0.0, -0.01, 0.02), (0.0, -0.01, 0.08), 0.01),
    "hand_palm_link": ((0.0, 0.0, -0.09), (0.0, 0.0, 0.0), 0.055),
}
"""The gripper as capsules in its links (ends and radius, m) round the SDF's collision boxes:
each finger's pad and the palm."""


def add_hsr(
    plant: MultibodyPlant, parser: Parser, model_file: str | Path | None = None
) -> ModelInstanceIndex:
    """Adds the HSR-B to ``plant`` (registering this project's package.xml if needed).

    ``model_file`` replaces the bundled model with another SDF file of the same joints.
    """
    package_map = parser.package_map()
    if not package_map.Contains(PACKAGE_NAME):
        package_map.AddPackageXml(str(PACKAGE_XML))
    if model_file is None:
        (instance,) = parser.AddModelsFromUrl(HSR_URL)
    else:
        (instance,) = parser.AddModels(file_name=str(model_file))
    return instance


@functools.cache
def head_limits() -> tuple[tuple[float, float], tuple[float, float]]:
    """The (lower, upper) position limits (rad) of HEAD_JOINTS in the bundled model."""
    plant = MultibodyPlant(0.0)
    add_hsr(plant, Parser(plant))
    plant.Finalize()
    pan, tilt = (plant.GetJointByName(name) for name in HEAD_JOINTS)
    return tuple(
        (float(joint.position_lower_limits()[0]), float(joint.position_upper_limits()[0]))
        for joint in (pan, tilt)
    )


def actuated_joint_names(plant: MultibodyPlant, instance: ModelInstanceIndex) -> list[str]:
    """Names of the actuated joints of ``instance`` in increasing actuator index order."""
    return [
        plant.get_joint_actuator(index).joint().name()
        for index in plant.GetJointActuatorIndices(instance)
    ]


def _resolve_positions(
    plant: MultibodyPlant, instance: ModelInstanceIndex, positions: Mapping[str, float]
) -> dict[str, float]:
    """Maps every actuated joint name to its value: given, or 0 when unspecified.

    Keys are actuated joint names, or "gripper" for the total fingertip opening (m), which
    sets hand_l_finger_joint to half of it.
    """
    names = actuated_joint_names(plant, instance)
    resolved = dict.fromkeys(names, 0.0)
    for key, value in positions.items():
        if key == GRIPPER_KEY:
            if GRIPPER_JOINT in positions:
                raise ValueError(f"give either '{GRIPPER_KEY}' or '{GRIPPER_JOINT}', not both")
            resolved[GRIPPER_JOINT] = FINGER_PER_OPENING * float(value)
        elif key in resolved:
            resolved[key] = float(value)
        else:
            raise ValueError(
                f"unknown HSR joint '{key}': expected '{GRIPPER_KEY}' or one of the actuated "
                f"joints {names} ({TORSO_JOINT} and {GRIPPER_MIMIC_JOINT} follow by mimic)"
            )
    return resolved


def hsr_desired_state(
    plant: MultibodyPlant, instance: ModelInstanceIndex, positions: Mapping[str, float]
) -> np.ndarray:
    """The vector [q_d, v_d] for ``plant.get_desired_state_input_port(instance)``.

    ``positions`` maps actuated joint names (or "gripper", the total fingertip opening in m)
    to desired positions; unspecified joints get 0 and all desired velocities are 0.

    Raises:
        ValueError: for a key that is not an actuated joint of the HSR or "gripper".
    """
    q_desired = np.array(list(_resolve_positions(plant, instance, positions).values()))
    return np.concatenate([q_desired, np.zeros_like(q_desired)])


def hsr_set_positions(
    plant: MultibodyPlant,
    plant_context: Context,
    instance: ModelInstanceIndex,
    positions: Mapping[str, float],
) -> None:
    """Sets the HSR's joint positions in ``plant_context``, keeping the mimic couplings.

    Same keys and defaults as :func:`hsr_desired_state` (unspecified joints are set to 0); the
    torso is set to half the arm lift and the right finger to the left one. Velocities are
    left untouched.
    """
    resolved = _resolve_positions(plant, instance, positions)
    resolved[TORSO_JOINT] = TORSO_PER_LIFT * resolved["arm_lift_joint"]
    resolved[GRIPPER_MIMIC_JOINT] = resolved[GRIPPER_JOINT]
    q = plant.GetPositions(plant_context).copy()
    for name, value in resolved.items():
        q[plant.GetJointByName(name, instance).position_start()] = value
    plant.SetPositions(plant_context, q)
