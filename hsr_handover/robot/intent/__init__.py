"""Pointing intent (paper 3.2, eqs. 16-17): which object the person wants, from a straight
pointing arm and the face's direction, held for a dwell time. Plain numpy, no Drake."""

from hsr_handover.robot.intent.rays import Ray, elbow_angle_deg, face_normal, ray_distances
from hsr_handover.robot.intent.tracker import IntentParams, IntentState, IntentTracker

__all__ = [
    "IntentParams", "IntentState", "IntentTracker", "Ray", "elbow_angle_deg", "face_normal",
    "ray_distances",
]  # fmt: skip
