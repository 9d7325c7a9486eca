"""Lifted keypoints that no body could hold: each pair of keypoints lies at most as far apart
as the bones between them are long, for the tallest person, plus the lifting's slack.

A keypoint's pixel on an occluding edge is lifted onto whatever is nearer there (the quarter of
the depth window nearest the camera is taken, so that a limb is not lost to the background
behind it). Seen past the robot's own arm, a shoulder can be lifted onto the arm, 75 cm from the
neck: the person's frame turns 65 degrees and their reach doubles. Such a keypoint disagrees
with most of the others; it is dropped, one at a time, the worst first, until the rest agree.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import shortest_path

from hsr_handover.interface.coco18 import COCO18_LIMBS, NUM_KEYPOINTS, keypoint_index

TALLEST_M = 2.05  # m: a person taller than nearly everyone
_BONE_PER_HEIGHT = {
    ("neck", "r_shoulder"): 0.13, ("neck", "l_shoulder"): 0.13,  # half the biacromial width
    ("r_shoulder", "r_elbow"): 0.186, ("l_shoulder", "l_elbow"): 0.186,
    ("r_elbow", "r_wrist"): 0.146, ("l_elbow", "l_wrist"): 0.146,
    ("neck", "r_hip"): 0.30, ("neck", "l_hip"): 0.30,
    ("r_hip", "r_knee"): 0.245, ("l_hip", "l_knee"): 0.245,
    ("r_knee", "r_ankle"): 0.246, ("l_knee", "l_ankle"): 0.246,
    ("neck", "nose"): 0.10, ("nose", "r_eye"): 0.035, ("nose", "l_eye"): 0.035,
    ("r_eye", "r_ear"): 0.06, ("l_eye", "l_ear"): 0.06,
}  # fmt: skip
"""Each COCO-18 limb's length per body height (Drillis and Contini 1966, as the person map's
arm uses them; the neck to a hip and to the nose measured on the same figure)."""
LIFT_SLACK_M = 0.15
"""m two lifted keypoints may lie beyond their bones' length: each is the body's surface seen
at its pixel, up to 13 cm off the joint (a shoulder whose arm points at the camera), plus the
pixel noise."""


def _reach_between() -> np.ndarray:
    """(18, 18) the longest any two keypoints can lie apart along the bones between them."""
    lengths = np.zeros((NUM_KEYPOINTS, NUM_KEYPOINTS))
    for (a, b), share in _BONE_PER_HEIGHT.items():
        i, j = keypoint_index(a), keypoint_index(b)
        lengths[i, j] = lengths[j, i] = share * TALLEST_M
    assert np.count_nonzero(lengths) == 2 * len(COCO18_LIMBS)  # every limb has its length
    return shortest_path(lengths, directed=False) + LIFT_SLACK_M


REACH_BETWEEN = _reach_between()
"""(18, 18) m: the farthest apart two lifted keypoints of one body may be."""


def body_consistent(points: np.ndarray, present: np.ndarray) -> np.ndarray:
    """(18,) bool: the `present` keypoints of the lifted `points` (18, 3) kept once those that
    lie too far from the others for one body (`REACH_BETWEEN`) are dropped, the keypoint with
    the most such disagreements first (of equal counts, the one farthest beyond)."""
    kept = np.asarray(present, dtype=bool).copy()
    points = np.where(kept[:, None], points, 0.0)
    distance = np.linalg.norm(points[:, None] - points[None], axis=2)
    excess = np.maximum(distance - REACH_BETWEEN, 0.0)
    while True:
        among = excess * kept[:, None] * kept[None]
        counts = (among > 0).sum(axis=1)
        if not counts.any():
            return kept
        worst = np.lexsort((among.sum(axis=1), counts))[-1]
        kept[worst] = False
