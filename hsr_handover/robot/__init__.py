"""The robot: what runs on the HSR, a Diagram joined to the station by ports only."""

from hsr_handover.robot.builder import Robot, build_robot, ready_command
from hsr_handover.robot.perception import PERCEPTION_OUTPUTS

__all__ = ["PERCEPTION_OUTPUTS", "Robot", "build_robot", "ready_command"]
