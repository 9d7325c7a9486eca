"""Whether an arm has just moved into its pose: a new gesture rises to point, an arm held out to
receive, or resting on the table, has stayed where it is.

A person who asks again raises the arm from wherever it was (at rest, or held out for the
object) to point, the wrist travelling a forearm's length or more; an arm held out to receive
stays still for seconds, its elbow angle flickering across eq. 16's threshold through the
detector's error (a short person's held-out arm reads 137-156 degrees, a pointing one 165-179).
A hand raised to point comes out toward the object, never back from it, while a resting wrist
lifted from depth as the robot's camera moves can slip 10-20 cm back onto the lap behind it.
"""

from __future__ import annotations

import collections

import numpy as np

from hsr_handover.robot.intent.person_rays import ARMS

RISEN_FRAMES = 3
"""Frames of the window in which the wrist must have been `rise_m` or more from where it is
now: the detector swaps the arms for a frame or two, putting a resting wrist 40 cm off, and a
real rise from rest takes a second of frames."""


class WristTrail:
    """Where each wrist has been over the last `window_s` seconds (m, world; NaN where
    unseen), and whether one came `rise_m` to where it is now, not away from where it
    points, in that time."""

    def __init__(self, rise_m: float, window_s: float):
        self.rise_m, self.window_s = rise_m, window_s
        self._trail: collections.deque[tuple[float, np.ndarray]] = collections.deque()

    def add(self, time: float, points: np.ndarray, confidence: np.ndarray) -> None:
        """Record both wrists of the lifted skeleton (18 x 3 points, 18 confidences) at `time`
        (s), and forget what is older than the window."""
        wrists = np.array([points[ARMS[arm][2]] for arm in ARMS], dtype=float)
        unseen = np.array([confidence[ARMS[arm][2]] <= 0 for arm in ARMS])
        wrists[unseen] = np.nan
        self._trail.append((time, wrists))
        while self._trail[0][0] < time - self.window_s:
            self._trail.popleft()

    def rose(self, arm: str, toward: np.ndarray) -> bool:
        """Whether the `arm`'s wrist ("right" or "left"), where last seen, lies at least
        `rise_m` from where it was, and not back from it along `toward` (where the arm
        points), in RISEN_FRAMES frames of the window."""
        side = list(ARMS).index(arm)
        seen = [wrists[side] for _, wrists in self._trail if np.isfinite(wrists[side]).all()]
        if not seen:
            return False
        travel = seen[-1] - np.array(seen)
        came = (np.linalg.norm(travel, axis=1) >= self.rise_m) & (travel @ toward >= 0.0)
        return bool(np.count_nonzero(came) >= RISEN_FRAMES)
