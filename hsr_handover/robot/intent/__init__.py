"""Pointing intent (paper 3.2, eqs. 16-17): which object the person wants, from a straight
pointing arm and the face's direction, held for a dwell time. Plain numpy, no Drake.

`rays` holds the vector geometry, `person_rays` the person's rays from a skeleton, `judging`
one frame's judgement, `smoothing` the rays over recent frames, `tracker` the dwell and the
correction watch, `params` the thresholds."""

from hsr_handover.robot.intent.params import IntentParams
from hsr_handover.robot.intent.rays import Ray, elbow_angle_deg, face_normal, ray_distances
from hsr_handover.robot.intent.tracker import IntentState, IntentTracker

__all__ = [
    "IntentParams", "IntentState", "IntentTracker", "Ray", "elbow_angle_deg", "face_normal",
    "ray_distances",
]  # fmt: skip
