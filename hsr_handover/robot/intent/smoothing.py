"""The rays over recent frames: the pointing ray's mean, the face's median and how fast the
pointing ray turns."""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np

from hsr_handover.robot.intent.judging import Observation
from hsr_handover.robot.intent.rays import Ray, angle_deg, heading_elevation, unit_direction


def _mean_ray(history: Sequence[tuple[float, Ray]]) -> Ray:
    direction = np.sum([ray.direction for _, ray in history], axis=0)
    origin = np.mean([ray.origin for _, ray in history], axis=0)
    return Ray(origin, direction / np.linalg.norm(direction))


def _median_ray(history: Sequence[tuple[float, Ray]]) -> Ray:
    """The rays' median heading and median elevation, from their median origin. The face's
    normal from three lifted points a few cm apart errs with heavy tails (staggered layout,
    1863 frames against the true keypoints' normal: sd 6.4 deg, but 3.3 deg from the median
    absolute deviation; the 5 x 5 depth window around a jittered eye pixel jumps between the
    eye and the skull): over a window of 20 frames the median's spread is 0.6 of the mean's."""
    directions = np.array([ray.direction for _, ray in history])
    total = directions.sum(axis=0)
    reference = math.atan2(total[1], total[0])  # headings unwrapped about the mean's
    headings, elevations = heading_elevation(directions)
    turns = (headings - reference + math.pi) % (2.0 * math.pi) - math.pi
    origin = np.median([ray.origin for _, ray in history], axis=0)
    heading = reference + float(np.median(turns))
    return Ray(origin, unit_direction(heading, float(np.median(elevations))))


def _since(
    history: Sequence[tuple[float, Ray]],
    start: float,
    central: Callable[[Sequence[tuple[float, Ray]]], Ray] = _mean_ray,
) -> Ray | None:
    """The `central` ray (mean or median) of the rays seen after `start` (s); None without
    any."""
    recent = [(t, ray) for t, ray in history if t > start - 1e-9]
    return central(recent) if recent else None


class RaySmoother:
    """The pointing ray's mean and the face's median (`_median_ray`) over the last `window`
    seconds, and how fast the pointing ray turns: the angle between the mean directions of the
    window's older and newer halves over the time between them (averaging first, so that the
    keypoints' jitter does not read as motion). A pointing ray's history restarts when the arm
    changes, or when it stops pointing for longer than `gap` seconds (until then, the window's
    rays stand for it, whichever other arm reads straight meanwhile: a pointing arm read bent
    for a frame lets a resting arm read straight that frame point instead, and restarting on
    it, and back, threw the gesture's hold away). Nor, while that arm is in its gap, does an
    arm whose ray passes near no object take the gesture from one that last pointed at an
    object: a standing person's hanging arm reads straight, and under twice the detector's
    error it took the gesture at each bent frame of the pointing arm, and gave it back, so that
    the hold was never read. An arm pointing at an object takes over from one pointing at
    nothing at once. A frame without a face adds nothing to the face's history but is given
    the window's face: the face seen in the last `window` seconds, never a guess (OpenPose
    drops a face point in about a quarter of frames; without a face seen in the window, there
    is no face). The face whose pitch is checked is the median over `pitch_window` seconds,
    from the same history."""

    MIN_FRAMES = 4  # for a turning rate: two frames in each half

    def __init__(self, window: float, gap: float = 0.0, pitch_window: float | None = None):
        self.window, self.gap = window, gap
        self.pitch_window = window if pitch_window is None else pitch_window
        self._pointing: list[tuple[float, Ray]] = []
        self._face: list[tuple[float, Ray]] = []  # over the longer of the two face windows
        self._arm: str | None = None
        self._bridging = False  # the last frame was in its arm's gap
        self._at_object = False  # the pointing arm's last ray passed near an object

    def __deepcopy__(self, memo: dict) -> RaySmoother:
        """Rays are never changed once made: a copy has its own histories, sharing the rays
        (Drake copies the state at each frame)."""
        clone = copy.copy(self)
        clone._pointing, clone._face = list(self._pointing), list(self._face)
        return clone

    def smooth(self, time: float, observation: Observation) -> Observation:
        in_gap = bool(self._pointing) and time - self._pointing[-1][0] <= self.gap + 1e-9
        other = observation.arm != self._arm and in_gap
        if other and (self._bridging or (self._at_object and not observation.at_object)):
            observation = dataclasses.replace(observation, arm=None, pointing=None)
        self._bridging = False
        if observation.pointing is not None:
            self._at_object = observation.at_object
        if observation.pointing is None and self._pointing:
            if in_gap:  # a gesture in a gap goes on
                observation = dataclasses.replace(observation, arm=self._arm)
                self._bridging = True
            else:
                self._pointing = []
        elif observation.arm != self._arm:
            self._pointing = []
        self._arm = observation.arm
        self._add(self._pointing, time, observation.pointing, self.window)
        self._add(self._face, time, observation.face, max(self.window, self.pitch_window))
        pointing = _since(self._pointing, time - self.window)
        face = _since(self._face, time - self.window, _median_ray)
        for_pitch = _since(self._face, time - self.pitch_window, _median_ray)
        sweep = self._sweep_deg_s() if pointing is not None else 0.0
        at_object = pointing is not None and self._at_object
        return dataclasses.replace(observation, pointing=pointing, face=face, sweep_deg_s=sweep,
                                   face_for_pitch=for_pitch, at_object=at_object)  # fmt: skip

    @staticmethod
    def _add(history: list, time: float, ray: Ray | None, window: float) -> None:
        if ray is not None:
            history.append((time, ray))
        history[:] = [(t, r) for t, r in history if t > time - window - 1e-9]

    def _sweep_deg_s(self) -> float:
        history = self._pointing
        if self.window <= 0:
            return 0.0  # no window, no rate: every frame is taken as held
        span = history[-1][0] - history[0][0]
        # Too early to tell a hold from a sweep, unless the frames are sparse (a slow camera
        # fits fewer than MIN_FRAMES in the window): then two frames half a window apart do.
        if len(history) < 2 or (len(history) < self.MIN_FRAMES and span < self.window / 2):
            return math.inf
        half = len(history) // 2
        older, newer = history[:half], history[half:]
        elapsed = np.mean([t for t, _ in newer]) - np.mean([t for t, _ in older])
        turn = angle_deg(_mean_ray(older).direction, _mean_ray(newer).direction)
        return turn / max(float(elapsed), 1e-9)
