"""Reachable ranges as Growing Cell Structures (paper 3.1, fig. 8): the robot's arm today."""

from hsr_handover.robot.effectivity import arm_map
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity, ArmMapParams, load_or_build

__all__ = ["ArmEffectivity", "ArmMapParams", "arm_map", "load_or_build"]
