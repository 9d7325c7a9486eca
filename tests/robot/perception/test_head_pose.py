"""The face's direction from the head's shape in a depth image, on ray-cast synthetic heads: a
round skull with a round nose standing out of it, as the simulated person's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.head_pose import NOSE_DROP_DEG, face_forward

CAMERA = PinholeCamera.from_fov_x(320, 240, 1.05)
# The head camera 1 m up, looking along world +x (camera x right = world -y, y down = -z).
X_WC = np.eye(4)
X_WC[:3, :3] = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]
X_WC[:3, 3] = [0.0, 0.0, 1.0]
SKULL = np.array([1.8, 0.1, 1.2])  # the skull's centre, 1.8 m in front of the camera
RADIUS = 0.095
NOSE, R_EYE, L_EYE = (keypoint_index(name) for name in ("nose", "r_eye", "l_eye"))


def _face_frame(yaw_deg: float, pitch_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(forward, left, up) of a head facing the camera (-x) turned by `yaw_deg` about the
    vertical and `pitch_deg` down."""
    yaw, pitch = math.radians(180.0 + yaw_deg), math.radians(-pitch_deg)
    forward = np.array([math.cos(pitch) * math.cos(yaw), math.cos(pitch) * math.sin(yaw),
                        math.sin(pitch)])  # fmt: skip
    left = np.array([-math.sin(yaw), math.cos(yaw), 0.0])
    return forward, left, np.cross(forward, left)


def _head(yaw_deg: float, pitch_deg: float, nose: bool = True) -> dict[str, np.ndarray]:
    """The spheres (centre, radius) and the face's keypoints of a head: the simulated
    person's proportions (eyes on the skull, the nose's centre 1.12 r ahead and 0.42 r below
    the eyes, its radius 0.18 r)."""
    forward, left, up = _face_frame(yaw_deg, pitch_deg)
    r = RADIUS
    points = {
        "nose": SKULL + r * (1.12 * forward - 0.42 * up),
        "r_eye": SKULL + r * (math.sqrt(1 - 0.34**2) * forward - 0.34 * left),
        "l_eye": SKULL + r * (math.sqrt(1 - 0.34**2) * forward + 0.34 * left),
    }
    spheres = [(SKULL, r)] + ([(points["nose"], 0.18 * r)] if nose else [])
    return {"spheres": spheres, "forward": forward, **points}


def _render(spheres: list[tuple[np.ndarray, float]]) -> np.ndarray:
    """Depth (H, W) of the nearest sphere along each pixel's ray; inf where none is hit."""
    v, u = np.indices((CAMERA.height, CAMERA.width), dtype=float)
    camera = np.stack([(u - CAMERA.cx) / CAMERA.fx, (v - CAMERA.cy) / CAMERA.fy, np.ones_like(u)])
    rays = np.einsum("ij,jhw->hwi", X_WC[:3, :3], camera)  # unit depth along each
    origin = X_WC[:3, 3]
    depth = np.full(u.shape, np.inf)
    for center, radius in spheres:
        # |origin + t ray - center|^2 = radius^2, t the depth along the optical axis
        a = np.einsum("hwi,hwi->hw", rays, rays)
        b = -2.0 * rays @ (center - origin)
        c = float((center - origin) @ (center - origin)) - radius**2
        disc = b * b - 4 * a * c
        hit = disc >= 0
        t = np.where(hit, (-b - np.sqrt(np.where(hit, disc, 0.0))) / (2 * a), np.inf)
        depth = np.minimum(depth, np.where(t > 0, t, np.inf))
    return depth.astype(np.float32)


def _pixels(head: dict, shift_px: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(18, 2) pixels and confidences with the nose and eyes detected (shifted right)."""
    pixels = np.full((NUM_KEYPOINTS, 2), np.nan)
    confidence = np.zeros(NUM_KEYPOINTS)
    for name, index in (("nose", NOSE), ("r_eye", R_EYE), ("l_eye", L_EYE)):
        pixels[index] = CAMERA.project(head[name][None], X_WC)[0][0] + [shift_px, 0.0]
        confidence[index] = 0.9
    return pixels, confidence


def _heading_deg(direction: np.ndarray) -> float:
    return math.degrees(math.atan2(direction[1], direction[0]))


def _elevation_deg(direction: np.ndarray) -> float:
    return math.degrees(math.atan2(direction[2], math.hypot(direction[0], direction[1])))


# A head bowed far holds the nose tip nearly below the skull's centre: a millimetre across
# turns its heading further.
@pytest.mark.parametrize(
    ("yaw", "pitch", "tolerance"), [(0, 0, 1.0), (25, 10, 1.0), (-35, 30, 1.0), (15, 45, 2.0)]
)
def test_the_face_points_where_the_head_faces(yaw, pitch, tolerance):
    head = _head(yaw, pitch)
    found = face_forward(_render(head["spheres"]), *_pixels(head), CAMERA, X_WC)
    assert found is not None
    heading_error = (_heading_deg(found) - _heading_deg(head["forward"]) + 180) % 360 - 180
    assert abs(heading_error) < tolerance
    # The nose's drop is the face model's: the simulated head's nose lies 20.6 deg below.
    assert abs(_elevation_deg(found) - _elevation_deg(head["forward"])) < 3.0
    assert np.linalg.norm(found) == pytest.approx(1.0)


def test_the_keypoints_only_say_where_to_look():
    """The eyes' and nose's pixels off by 2 px (6 mm at 1.8 m) turn eq. 17's heading by
    degrees; the head's shape does not move."""
    head = _head(20, 20)
    depth = _render(head["spheres"])
    exact = face_forward(depth, *_pixels(head), CAMERA, X_WC)
    shifted = face_forward(depth, *_pixels(head, shift_px=2.0), CAMERA, X_WC)
    assert exact is not None and shifted is not None
    assert abs(_heading_deg(exact) - _heading_deg(shifted)) < 0.5


def test_a_head_without_a_nose_gives_no_direction():
    head = _head(10, 20, nose=False)
    assert face_forward(_render(head["spheres"]), *_pixels(head), CAMERA, X_WC) is None


def test_a_head_turned_away_gives_no_direction():
    """Turned 100 deg from the camera the nose is seen edge on, if at all."""
    head = _head(100, 10)
    assert face_forward(_render(head["spheres"]), *_pixels(head), CAMERA, X_WC) is None


def test_without_the_nose_keypoint_there_is_no_direction():
    head = _head(0, 20)
    pixels, confidence = _pixels(head)
    confidence[NOSE] = 0.0
    assert face_forward(_render(head["spheres"]), pixels, confidence, CAMERA, X_WC) is None


def test_a_face_without_depth_gives_no_direction():
    head = _head(0, 20)
    empty = np.full((CAMERA.height, CAMERA.width), np.nan, dtype=np.float32)
    assert face_forward(empty, *_pixels(head), CAMERA, X_WC) is None


def test_a_hand_beside_the_face_is_neither_skull_nor_nose():
    """A hand 15 cm in front of the face and beside it lies in the head's window and depth
    band: the skull's refits leave it out."""
    head = _head(15, 20)
    hand = (SKULL + np.array([-0.22, -0.09, 0.0]), 0.04)
    found = face_forward(_render([*head["spheres"], hand]), *_pixels(head), CAMERA, X_WC)
    assert found is not None
    assert abs(_heading_deg(found) - _heading_deg(head["forward"])) < 1.5


def test_the_drop_raises_the_tip_in_its_vertical_plane():
    head = _head(30, 0)
    found = face_forward(_render(head["spheres"]), *_pixels(head), CAMERA, X_WC)
    tip = head["nose"] - SKULL
    assert _elevation_deg(found) == pytest.approx(_elevation_deg(tip) + NOSE_DROP_DEG, abs=1.5)
