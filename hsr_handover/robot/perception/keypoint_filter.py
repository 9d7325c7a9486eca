"""Tracking one person's lifted keypoints over time: a filter that smooths them, rejects a
detector's outliers and swapped arms, and bridges short misses (numpy only).

A pose detector errs in ways that one frame cannot show: it swaps the arms' labels for a few
frames, reports a wrist on an object beside the hand, and loses a wrist or a face point for a
run of frames (`perception.detector_model` simulates each). Each keypoint here is followed by
its own Kalman filter in the world frame (the camera moves; the world does not), with a
constant-velocity model driven by white-noise acceleration `acceleration_sd`. The default,
50 m/s^2, smooths little: the recogniser already averages its rays over a second, and lifted
keypoints jump 5-15 cm in depth, legitimately, when the depth window slips between a limb and
what is behind it. On the intent experiment's recorded percepts (generated layouts, seed 1,
120 requests and 40 distractors, realistic detector) 2 m/s^2, which halves a still person's
jitter and follows a pointing reach within 8 cm, read 86.7 % of requests; 50 m/s^2 89.2 %;
no filter 87.5 %; all with no false trigger (with the ideal detector: 92.5 %, 93.3 %). On the
intent reference (60 requests) it reads 88.3 % against 91.7 % without: over both, 160 of 180
either way, the difference the bridging of misses (`hold_s`).

- **Confidence-aware.** A measurement's variance is `measurement_sd_m`^2 over its confidence
  squared: OpenPose's confidence falls where the image evidence is weak, and a low-confidence
  keypoint moves the track less.
- **Outliers.** A measurement farther from the prediction than `gate_sd` standard deviations
  (the innovation's, taken at full confidence: a keypoint far from where the person's body is
  is an outlier however the detector scores it) is not used; at the defaults, a jump of more
  than about 30 cm in one frame. A keypoint that really moved that fast is taken up again
  once `reacquire_frames` frames in a row agree on where it is now. (A wrist reported on a
  cup within reach passes the gate; its lower confidence is what weighs it less.)
- **Swaps.** Before the update, the two arms' measurements are matched to the two arms' tracks
  both ways; the labels are exchanged when the crossed match is much the better (its summed
  squared innovations under `swap_ratio` of the direct match's). A nearest-track test, not
  bone lengths: a swapped arm has the body's own lengths.
- **Misses.** A keypoint unseen for up to `hold_s` is reported where its track predicts, with
  its confidence halved; longer, it is missing.

Its output keeps the conventions of `Skeleton`: confidence 0 exactly where a keypoint is
missing, a finite point wherever it is not.
"""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index

_ARMS = (
    [keypoint_index(f"r_{joint}") for joint in ("shoulder", "elbow", "wrist")],
    [keypoint_index(f"l_{joint}") for joint in ("shoulder", "elbow", "wrist")],
)
MIN_CONFIDENCE = 0.1  # a measurement's weight floor: confidence 0 means missing
HELD_CONFIDENCE_SHARE = 0.5
TRACK_LOST_S = 0.5  # unseen this long, a keypoint's velocity no longer says where it is


@dataclasses.dataclass(frozen=True)
class KeypointFilterParams:
    """measurement_sd_m: a lifted keypoint's error per axis (m) at confidence 1, (0, 1].
    acceleration_sd: the keypoints' white-noise acceleration (m/s^2 per axis), (0, 100].
    gate_sd: innovations beyond this many standard deviations are outliers, (0, 100].
    reacquire_frames: outliers in a row that agree (within the gate of each other) move the
    track there, an integer in [1, 100]. swap_ratio: the crossed match of the arms wins below
    this share of the direct one's cost, (0, 1]. hold_s: how long (s) an unseen keypoint is
    reported from its track, [0, 10]."""

    measurement_sd_m: float = 0.03
    acceleration_sd: float = 50.0
    gate_sd: float = 4.0
    reacquire_frames: int = 3
    swap_ratio: float = 0.25
    hold_s: float = 0.2

    def __post_init__(self) -> None:
        ranges = {"measurement_sd_m": (0.0, 1.0), "acceleration_sd": (0.0, 100.0),
                  "gate_sd": (0.0, 100.0), "swap_ratio": (0.0, 1.0)}  # fmt: skip
        for name, (low, high) in ranges.items():
            value = getattr(self, name)
            if not low < value <= high:
                raise ValueError(f"{name}: expected in ({low:g}, {high:g}], got {value}")
        if not (isinstance(self.reacquire_frames, int) and 1 <= self.reacquire_frames <= 100):
            raise ValueError(
                f"reacquire_frames: expected an integer in [1, 100], got {self.reacquire_frames}"
            )
        if not 0 <= self.hold_s <= 10:
            raise ValueError(f"hold_s: expected in [0, 10] s, got {self.hold_s}")


class KeypointFilter:
    """One person's keypoints followed frame by frame (see the module's docstring)."""

    def __init__(self, params: KeypointFilterParams | None = None):
        self.params = KeypointFilterParams() if params is None else params
        n = NUM_KEYPOINTS
        self._position = np.full((n, 3), np.nan)
        self._velocity = np.zeros((n, 3))
        self._covariance = np.zeros((n, 2, 2))  # (position, velocity) per axis, alike on each
        self._seen = np.full(n, -math.inf)  # when each was last measured
        self._confidence = np.zeros(n)
        self._outliers: list[list[np.ndarray]] = [[] for _ in range(n)]
        self._time = math.nan
        self.swaps = 0  # how many frames had their arms exchanged
        self.rejected = 0  # how many measurements were taken for outliers

    def __deepcopy__(self, memo: dict) -> KeypointFilter:
        clone = copy.copy(self)
        for name in ("_position", "_velocity", "_covariance", "_seen", "_confidence"):
            setattr(clone, name, getattr(self, name).copy())
        clone._outliers = [list(outliers) for outliers in self._outliers]
        return clone

    def update(
        self, time: float, points: np.ndarray, confidence: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Take the frame captured at `time` (s): lifted `points` (18, 3) and their confidences
        (18,; 0 missing). Returns the filtered points (18, 3) and confidences (18,)."""
        points = np.asarray(points, dtype=float)
        confidence = np.asarray(confidence, dtype=float)
        measured = (confidence > 0) & np.isfinite(points).all(axis=1)
        self._predict(time)
        points, confidence, measured = self._unswapped(points, confidence, measured)
        for i in np.flatnonzero(measured):
            self._measure(i, points[i], float(confidence[i]), time)
        return self._output(time)

    def _predict(self, time: float) -> None:
        dt = 0.0 if math.isnan(self._time) else max(time - self._time, 0.0)
        self._time = time
        if dt == 0.0:
            return
        transition = np.array([[1.0, dt], [0.0, 1.0]])
        q = self.params.acceleration_sd**2
        noise = q * np.array([[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]])
        tracked = np.isfinite(self._position).all(axis=1)
        self._position[tracked] += dt * self._velocity[tracked]
        self._covariance[tracked] = transition @ self._covariance[tracked] @ transition.T + noise

    def _distance2(self, i: int, point: np.ndarray) -> float:
        """The squared innovation of `point` against track `i` over its variance at full
        confidence (inf without a track)."""
        if not np.isfinite(self._position[i]).all():
            return math.inf
        variance = self._covariance[i, 0, 0] + self.params.measurement_sd_m**2
        return float(np.sum((point - self._position[i]) ** 2) / variance)

    def _arm_cost(self, points: np.ndarray, measured: np.ndarray, crossed: bool) -> float:
        cost = 0.0
        for side in (0, 1):
            track = _ARMS[1 - side if crossed else side]
            for joint, i in enumerate(_ARMS[side]):
                if measured[i]:
                    cost += min(self._distance2(track[joint], points[i]), 1e6)
        return cost

    def _unswapped(self, points, confidence, measured):
        """The frame with its arms' labels exchanged when the crossed match is much better."""
        direct = self._arm_cost(points, measured, crossed=False)
        crossed = self._arm_cost(points, measured, crossed=True)
        gate = self.params.gate_sd**2
        if not (direct > gate and crossed < self.params.swap_ratio * direct):
            return points, confidence, measured
        self.swaps += 1
        order = np.arange(NUM_KEYPOINTS)
        order[_ARMS[0] + _ARMS[1]] = _ARMS[1] + _ARMS[0]
        return points[order], confidence[order], measured[order]

    def _measure(self, i: int, point: np.ndarray, confidence: float, time: float) -> None:
        distance2 = self._distance2(i, point)
        if math.isinf(distance2) or time - self._seen[i] > TRACK_LOST_S:
            self._restart(i, point, confidence, time)
            return
        if distance2 > self.params.gate_sd**2:
            self.rejected += 1
            outliers = self._outliers[i]
            outliers.append(point)
            spread = self.params.gate_sd * self.params.measurement_sd_m * math.sqrt(2.0)
            agree = all(np.linalg.norm(p - point) <= spread for p in outliers)
            if not agree:
                self._outliers[i] = [point]
            elif len(outliers) >= self.params.reacquire_frames:
                self._restart(i, point, confidence, time)
            return
        self._outliers[i] = []
        variance = (self.params.measurement_sd_m / max(confidence, MIN_CONFIDENCE)) ** 2
        covariance = self._covariance[i]
        gain = covariance[:, 0] / (covariance[0, 0] + variance)
        innovation = point - self._position[i]
        self._position[i] += gain[0] * innovation
        self._velocity[i] += gain[1] * innovation
        self._covariance[i] = covariance - np.outer(gain, covariance[0])
        self._seen[i], self._confidence[i] = time, confidence

    def _restart(self, i: int, point: np.ndarray, confidence: float, time: float) -> None:
        """A new track at `point`, still, its speed unknown up to an arm's."""
        variance = (self.params.measurement_sd_m / max(confidence, MIN_CONFIDENCE)) ** 2
        self._position[i], self._velocity[i] = point, 0.0
        self._covariance[i] = np.diag([variance, 1.0])
        self._seen[i], self._confidence[i] = time, confidence
        self._outliers[i] = []

    def _output(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        age = time - self._seen
        now = age <= 1e-9
        held = ~now & (age <= self.params.hold_s + 1e-9)
        confidence = np.where(now, self._confidence, 0.0)
        confidence[held] = HELD_CONFIDENCE_SHARE * self._confidence[held]
        present = confidence > 0
        points = np.where(present[:, None], self._position, np.nan)
        return points, confidence
