"""The recogniser's thresholds (paper 3.2), each with its range."""

from __future__ import annotations

import dataclasses

from hsr_handover.literature import HEAD_FRACTION_SD, STIEFELHAGEN_HEAD_FRACTION

HEAD_SHARE_SPREAD = 2.0 * HEAD_FRACTION_SD / STIEFELHAGEN_HEAD_FRACTION
"""Twice the spread of the head's share of a gaze shift between people, over the usual share
(2 x 0.08 / 0.689 = 0.23): how far, as a share of the eyes' turn, the gaze read from the face
as that turn times `head_gain` may miss for a person whose head makes more or less of it."""

POINTING_RAYS = ("shoulder_wrist", "elbow_wrist", "eye_wrist")
"""Where the pointing ray starts (it always runs through the wrist): the shoulder, the elbow
(eq. 16's forearm) or the midpoint of the eyes (people align eye, finger and target)."""

_RANGES = {  # (low, high, unit, whether low itself is allowed)
    "straight_arm_deg": (90.0, 180.0, "deg", False), "d_min": (0.0, 2.0, "m", False),
    "gaze_tolerance_deg": (0.0, 90.0, "deg", False), "t_max": (0.0, 10.0, "s", True),
    "gaze_pitch_tolerance_deg": (0.0, 90.0, "deg", False), "gaze_weight": (0.0, 10.0, "", False),
    "gaze_pitch_tolerance_share": (0.0, 1.0, "", True),
    "gaze_tolerance_share": (0.0, 1.0, "", True),
    "head_gain": (1.0, 3.0, "", True), "face_tilt_deg": (0.0, 90.0, "deg", True),
    "smoothing_s": (0.0, 10.0, "s", True), "steady_deg_s": (0.0, 1000.0, "deg/s", False),
    "bent_gap_s": (0.0, 10.0, "s", True), "pitch_smoothing_s": (0.0, 10.0, "s", True),
    "correction_gaze_tolerance_deg": (0.0, 90.0, "deg", False),
    "correction_below_deg": (0.0, 90.0, "deg", False),
    "rise_m": (0.0, 1.0, "m", True), "rise_s": (0.0, 10.0, "s", False),
}  # fmt: skip


@dataclasses.dataclass(frozen=True)
class IntentParams:
    """The recogniser's thresholds (paper 3.2). The defaults are the best measured on recorded
    percepts (`benchmarks/sweep_intent.py`): docs/intent.md says why, docs/results_history.md
    what was measured.

    straight_arm_deg: eq. 16's elbow angle from which an arm counts as pointing.
    d_min: how near (m) the pointing ray must pass an object's centre.
    gaze_tolerance_deg: how far (deg, horizontally) the estimated gaze may be off the object.
    gaze_tolerance_share: or, when more, this share of how far the eyes turn from the torso's
    forward direction to the object (`HEAD_SHARE_SPREAD`): the gaze is read as the face's
    turn times `head_gain`, and misses by the person's own head share's difference from the
    usual, in proportion to the turn. Generated layouts place objects up to 60 degrees from
    the torso's front, where a head that makes 0.85 of the shift (two spreads over the usual
    0.689) reads 14 degrees past the object: the fixed 12 degrees refused arms plainly on it.
    gaze_pitch_tolerance_deg: how far (deg) the estimated gaze may pass above the object.
    gaze_pitch_tolerance_share: or, when more, this share of how far the eyes look down to the
    object. The head makes its own person's share of a gaze shift, down as across, and the
    pitch read from it is scaled by the usual share's inverse (`head_gain`): a head that makes
    less reads above the object by a share of the whole look down. Twice the spread of the
    head's share (2 x 0.08 / 0.689 = 0.23): a standing person looks 45 degrees down to the
    table and a 1.80 m one can read 9-10 degrees above the cup asked for; a seated person
    looks about 30 degrees down, where 8 degrees holds.
    gaze_weight: how much the gaze counts against the arm in choosing between the objects both
    allow (the weight of the gaze's term in `judge`'s score). Weighed as the arm, the gaze
    chooses the neighbour of an object the arm plainly points at; weighed much less, a lifted
    arm biased across the body wins.
    t_max: how long (s) the same object must be asked for.
    pointing_ray: one of POINTING_RAYS.
    head_gain: the eyes' turn over the head's (1 / 0.689, Stiefelhagen and Zhu 2002).
    face_from_head_shape: read the face's direction from the head's shape in the depth image
    (`robot.perception.head_pose`: the skull's centre to the nose tip) where it is found, and
    from eq. 17's nose-eyes plane elsewhere. Over a gesture it errs 0.55 deg where eq. 17 on
    the realistic detector's lifted keypoints errs 2.4.
    face_tilt_deg: eq. 17's nose-eyes plane faces up by this much when the head faces level
    (the nose tip is below and a little ahead of the eyes: 23 deg on the simulated face's
    keypoints, 30 deg on the lifted skeleton, whose eyes are read a little deeper than the
    nose).
    smoothing_s: the rays are averaged over the frames of the last `smoothing_s` seconds
    (the pointing ray's mean, the face's median heading and elevation).
    pitch_smoothing_s: the face whose pitch is checked against `gaze_pitch_tolerance_deg` is
    averaged over this longer window (the horizontal bearing keeps `smoothing_s`, so a turn
    of the head is read as soon): the nose-eyes plane tilts by degrees from frame to frame,
    and a few frames that dip would otherwise complete the dwell of an arm lying on the table
    toward a cup while the eyes look 11-12 degrees above it.
    steady_deg_s: the pointing ray counts only while it turns slower than this (deg/s) over
    that window: a gesture is read in its hold, not while the arm sweeps toward the target.
    The detector's error reads as turning too: with it doubled, a held arm's ray turns
    30-45 deg/s between the window's halves now and then, and a stricter bound broke holds;
    bridged through its bent readings (`bent_gap_s`), more than that.
    bent_gap_s: how long (s) a pointing arm may read bent, or go unseen, before its gesture
    ends; meanwhile its frames are judged with the rays it showed in the last `smoothing_s`
    (an arm pointing across the body or at the camera is foreshortened, and its lifted elbow
    lands on the forearm: the elbow angle of a held arm flickers between 100 and 170 deg).
    With the detector's error doubled a held arm reads bent for runs of frames: 0.3 s reads
    them through, where 0.2 s lost one request in twenty; 0.5 s bridged an arm held out to receive
    into a gesture that never ended, and a person's correction went unseen.
    correction_gaze_tolerance_deg: `gaze_tolerance_deg` for a correction (see
    `IntentTracker`): the object first recognised is left out, and with it the neighbour the
    person's gaze was confused with; the same person's gaze misses the same way again (a head
    that turns half of a gaze shift reads the red cup 42 degrees off as the yellow box at 30).
    correction_below_deg: how far (deg) the eyes may look below the object a correction asks
    for: a hand held out to receive is a straight arm toward the table, and the eyes on it
    look 14-16 degrees below the objects beyond.
    rise_m, rise_s: a request, and a correction, is a new gesture: its wrist come at least
    `rise_m` (m) to where it points, and not back from it, from within the last `rise_s` (s)
    when its dwell starts (`WristTrail`). An arm held out to receive, or resting on the table,
    reads straight now and then but has not moved (a seated person's forearm lying toward the
    camera reads straight at a cup while the eyes rest on another). The arm rises from rest
    or from holding out, 10-30 cm; the held-out arm's filtered wrist wanders 5 cm. The window is
    shorter than the time from the person holding a hand out (at most 6 s after the pointing's
    onset) to the watch waking (once the robot lifts, about 8 s or more after it). A person
    the robot finds already pointing is read once they point again.
    track_keypoints: follow each keypoint over time before reading the rays
    (`robot.perception.keypoint_filter`: smoothed, outliers and swapped arms rejected, short
    misses bridged).
    Ranges: each in [low, high] of `_RANGES`; pointing_ray one of POINTING_RAYS.
    """

    straight_arm_deg: float = 150.0
    d_min: float = 0.4
    gaze_tolerance_deg: float = 12.0
    gaze_tolerance_share: float = HEAD_SHARE_SPREAD
    gaze_pitch_tolerance_deg: float = 8.0
    gaze_pitch_tolerance_share: float = HEAD_SHARE_SPREAD
    gaze_weight: float = 0.4
    t_max: float = 0.3
    pointing_ray: str = "shoulder_wrist"
    head_gain: float = 1.0 / STIEFELHAGEN_HEAD_FRACTION
    face_from_head_shape: bool = True
    face_tilt_deg: float = 30.0
    smoothing_s: float = 1.0
    pitch_smoothing_s: float = 1.5
    steady_deg_s: float = 60.0
    bent_gap_s: float = 0.3
    correction_gaze_tolerance_deg: float = 24.0
    correction_below_deg: float = 10.0
    rise_m: float = 0.08
    rise_s: float = 2.0
    track_keypoints: bool = True

    def __post_init__(self) -> None:
        for name, (low, high, unit, closed) in _RANGES.items():
            value = getattr(self, name)
            if not (low <= value if closed else low < value) or not value <= high:
                interval = f"{'[('[not closed]}{low:g}, {high:g}] {unit}".rstrip()
                raise ValueError(f"{name}: expected {interval}, got {value}")
        if self.pointing_ray not in POINTING_RAYS:
            raise ValueError(f"pointing_ray: expected one of {POINTING_RAYS}")
