"""Following one person through a recording of OpenPose detections (numpy only).

OpenPose lists the people of each frame in no stable order, so taking `people[0]` jumps between
people whenever several are in view. Here the person of interest is chosen once and then
followed frame to frame by where their keypoints are:

- **Choosing** (`choose_person`): the person nearest a configured image point (`near_px`), or by
  default the one facing the camera (nose and both eyes seen, and their right shoulder on the
  image's left of their left shoulder, as for anyone facing the lens) with the widest shoulders,
  that is the nearest to the camera: the person at the table facing the robot. Without anyone
  facing the camera, the widest shoulders of anyone; without shoulders, the largest body.
- **Following** (`PersonTracker`): in each frame, the person whose keypoints lie nearest the
  last skeleton seen of the tracked person (`mean_keypoint_distance`), accepted only within
  `max_jump_shoulders` shoulder widths; otherwise the tracked person is taken to be absent from
  that frame, and the last skeleton seen is kept to find them again. After
  `reselect_after_frames` frames without them, the person of interest is chosen afresh.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.keypoints import Detection

NO_PERSON = "no person in the frame"
TRACKED_PERSON_ABSENT = "tracked person not in the frame"

# Between consecutive frames (30 Hz) a person's keypoints move on average well under a tenth of
# their shoulder width, even while an arm swings to point; a second person beside them has
# keypoints at least about one shoulder width away on average, since two bodies side by side
# cannot overlap. Half a shoulder width lies between the two: it keeps the tracked person through
# OpenPose's jitter and a few missed frames, and does not jump to a neighbour when they vanish.
MAX_JUMP_SHOULDERS = 0.5
# One second at OpenPose's usual 30 frames per second: a person who has been gone that long may
# come back anywhere, so the person of interest is chosen again by the first frame's rule.
RESELECT_AFTER_FRAMES = 30
# When a skeleton has no pair of shoulders, its shoulder width is estimated as this share of the
# diagonal of its keypoints' bounding box (an adult's 0.4 m shoulders over 1.7 m of height, about
# a quarter), and never below MIN_BODY_SCALE_PX so that a distant person's jitter still passes.
SHOULDERS_PER_BOX_DIAGONAL = 0.25
MIN_BODY_SCALE_PX = 4.0

_NOSE, _R_EYE, _L_EYE = (keypoint_index(n) for n in ("nose", "r_eye", "l_eye"))
_R_SHOULDER, _L_SHOULDER = keypoint_index("r_shoulder"), keypoint_index("l_shoulder")


def _seen(person: Detection) -> np.ndarray:
    """(18,) bool: the keypoints the detector found."""
    return person.confidence > 0


def keypoint_centre(person: Detection) -> np.ndarray | None:
    """The mean pixel (u, v) of a person's found keypoints, or None when none was found."""
    seen = _seen(person)
    return person.pixels[seen].mean(axis=0) if seen.any() else None


def shoulder_width_px(person: Detection) -> float:
    """Pixels between the two shoulders, NaN unless both were found."""
    if not (_seen(person)[_R_SHOULDER] and _seen(person)[_L_SHOULDER]):
        return math.nan
    return float(np.linalg.norm(person.pixels[_R_SHOULDER] - person.pixels[_L_SHOULDER]))


def body_scale_px(person: Detection) -> float:
    """A person's shoulder width in pixels for gating: the larger of the measured width (when
    both shoulders were found) and the estimate from the keypoints' bounding box (see
    SHOULDERS_PER_BOX_DIAGONAL), which stands in for a person seen side on, whose shoulders
    overlap in the image. NaN when no keypoint was found."""
    pixels = person.pixels[_seen(person)]
    if len(pixels) == 0:
        return math.nan
    diagonal = float(np.linalg.norm(pixels.max(axis=0) - pixels.min(axis=0)))
    width = shoulder_width_px(person)
    measured = width if math.isfinite(width) else 0.0
    return max(measured, SHOULDERS_PER_BOX_DIAGONAL * diagonal, MIN_BODY_SCALE_PX)


def faces_camera(person: Detection) -> bool:
    """Nose and both eyes found, and the right shoulder left of the left one in the image (a
    person facing the lens shows their right side on the image's left)."""
    seen = _seen(person)
    if not seen[[_NOSE, _R_EYE, _L_EYE, _R_SHOULDER, _L_SHOULDER]].all():
        return False
    return bool(person.pixels[_R_SHOULDER, 0] < person.pixels[_L_SHOULDER, 0])


def mean_keypoint_distance(a: Detection, b: Detection) -> float:
    """Mean pixel distance between the keypoints found in both detections; NaN when they share
    none."""
    both = _seen(a) & _seen(b)
    if not both.any():
        return math.nan
    return float(np.linalg.norm(a.pixels[both] - b.pixels[both], axis=1).mean())


def choose_person(
    people: Sequence[Detection], near_px: tuple[float, float] | None = None
) -> int | None:
    """The index of the person of interest among one frame's `people` (see the module
    docstring), or None when nobody has a keypoint."""
    candidates = [i for i, person in enumerate(people) if _seen(person).any()]
    if not candidates:
        return None
    if near_px is not None:
        target = np.asarray(near_px, dtype=float)
        return min(candidates, key=lambda i: np.linalg.norm(keypoint_centre(people[i]) - target))
    facing = [i for i in candidates if faces_camera(people[i])]
    with_shoulders = [i for i in candidates if math.isfinite(shoulder_width_px(people[i]))]
    for group in (facing, with_shoulders):
        if group:
            return max(group, key=lambda i: shoulder_width_px(people[i]))
    return max(candidates, key=lambda i: body_scale_px(people[i]))


class PersonTracker:
    """Follows one person through a sequence of frames: `update(people)` with each frame's
    detections gives the tracked person's Detection, or an empty one whose status says why
    (NO_PERSON, TRACKED_PERSON_ABSENT)."""

    def __init__(
        self,
        near_px: tuple[float, float] | None = None,
        max_jump_shoulders: float = MAX_JUMP_SHOULDERS,
        reselect_after_frames: int | None = RESELECT_AFTER_FRAMES,
    ):
        if not max_jump_shoulders > 0:
            raise ValueError(f"max_jump_shoulders: expected > 0, got {max_jump_shoulders}")
        if reselect_after_frames is not None and reselect_after_frames < 1:
            raise ValueError(
                f"reselect_after_frames: expected None or >= 1, got {reselect_after_frames}"
            )
        self.near_px = near_px
        self.max_jump_shoulders = max_jump_shoulders
        self.reselect_after_frames = reselect_after_frames
        self.last_seen: Detection | None = None  # the tracked person's last skeleton
        self._scale_px = math.nan  # their last measured size (body_scale_px)
        self._frames_absent = 0

    def update(self, people: Sequence[Detection]) -> Detection:
        """The tracked person in this frame's `people`."""
        people = [person for person in people if _seen(person).any()]
        if not people:
            return self._absent(NO_PERSON)
        if self.last_seen is None or self._should_reselect():
            self._scale_px = math.nan  # a new person of interest: forget the old one's size
            return self._follow(people[choose_person(people, self.near_px)])
        distances = [mean_keypoint_distance(self.last_seen, person) for person in people]
        distances = [d if math.isfinite(d) else math.inf for d in distances]
        nearest = int(np.argmin(distances))
        if distances[nearest] > self.max_jump_shoulders * self._scale_px:
            return self._absent(TRACKED_PERSON_ABSENT)
        return self._follow(people[nearest])

    def _should_reselect(self) -> bool:
        limit = self.reselect_after_frames
        return limit is not None and self._frames_absent >= limit

    def _follow(self, person: Detection) -> Detection:
        # A skeleton without both shoulders gives only a rough size: keep a measured one.
        if math.isfinite(shoulder_width_px(person)) or not math.isfinite(self._scale_px):
            self._scale_px = body_scale_px(person)
        self.last_seen, self._frames_absent = person, 0
        return person

    def _absent(self, reason: str) -> Detection:
        self._frames_absent += 1
        return Detection.missing(reason)


def track_person(
    frames: Iterable[Sequence[Detection]], near_px: tuple[float, float] | None = None
) -> list[Detection]:
    """The person of interest in each frame of `frames` (each a frame's people), followed with
    a PersonTracker; an empty Detection where they are not seen."""
    tracker = PersonTracker(near_px)
    return [tracker.update(people) for people in frames]
