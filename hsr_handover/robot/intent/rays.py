"""The geometry of pointing and gaze: the elbow angle (eq. 16), the face normal (eq. 17), the
rays they give and how far an object lies from a ray."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

_EPS = 1e-9


@dataclasses.dataclass(frozen=True)
class Ray:
    """A half-line from `origin` along the unit vector `direction` (world frame, m)."""

    origin: np.ndarray
    direction: np.ndarray

    @classmethod
    def through(cls, start: np.ndarray, through: np.ndarray) -> Ray | None:
        """The ray from `start` through `through`; None when the two points coincide."""
        along = np.asarray(through, dtype=float) - np.asarray(start, dtype=float)
        length = float(np.linalg.norm(along))
        if not length > _EPS:
            return None
        return cls(np.asarray(start, dtype=float), along / length)


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (degrees) between two vectors; NaN when either has no length."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    norms = float(np.linalg.norm(a) * np.linalg.norm(b))
    if not norms > _EPS:
        return math.nan
    return math.degrees(math.acos(float(np.clip(a @ b / norms, -1.0, 1.0))))


def elbow_angle_deg(shoulder: np.ndarray, elbow: np.ndarray, wrist: np.ndarray) -> float:
    """Eq. 16: the angle at the elbow u0 between the shoulder u1 and the wrist u2 (degrees;
    180 for a straight arm). NaN when a segment has no length."""
    return angle_deg(np.asarray(shoulder) - elbow, np.asarray(wrist) - elbow)


def face_normal(nose: np.ndarray, r_eye: np.ndarray, l_eye: np.ndarray) -> np.ndarray | None:
    """Eq. 17: N = (v0 - v1) x (v0 - v2) of the nose v0 and the eyes, normalised and turned to
    face away from the head. With v1 the right eye and v2 the left, the cross product points
    into the head (the right eye is on the person's right), so the result is -N. None when the
    three points are (nearly) collinear."""
    normal = np.cross(np.asarray(nose) - r_eye, np.asarray(nose) - l_eye)
    length = float(np.linalg.norm(normal))
    if not length > _EPS:
        return None
    return -normal / length


def heading_elevation(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The heading about world z and the elevation from level (rad) of each direction (N, 3)."""
    directions = np.asarray(directions, dtype=float).reshape(-1, 3)
    horizontal = np.hypot(directions[:, 0], directions[:, 1])
    return np.arctan2(directions[:, 1], directions[:, 0]), np.arctan2(directions[:, 2], horizontal)


def unit_direction(heading: float, elevation: float) -> np.ndarray:
    """The unit vector at `heading` about world z and `elevation` from level (rad)."""
    level = math.cos(elevation)
    return np.array([level * math.cos(heading), level * math.sin(heading), math.sin(elevation)])


def tilt_down(direction: np.ndarray, degrees: float) -> np.ndarray:
    """`direction` turned down (toward world -z) by `degrees` in its vertical plane."""
    horizontal = float(np.hypot(direction[0], direction[1]))
    if horizontal < _EPS:
        return np.asarray(direction, dtype=float)
    elevation = math.atan2(direction[2], horizontal) - math.radians(degrees)
    heading = np.array([direction[0], direction[1]]) / horizontal
    return np.array([*(math.cos(elevation) * heading), math.sin(elevation)])


def ray_distances(ray: Ray, points: np.ndarray) -> np.ndarray:
    """Distance (m) from each point (N, 3) to the ray: perpendicular where the point lies ahead
    of the origin, the distance to the origin where it lies behind."""
    offsets = np.asarray(points, dtype=float).reshape(-1, 3) - ray.origin
    along = np.clip(offsets @ ray.direction, 0.0, None)
    return np.linalg.norm(offsets - along[:, None] * ray.direction, axis=1)
