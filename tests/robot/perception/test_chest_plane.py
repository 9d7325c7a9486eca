"""The torso's facing from the chest's plane in a depth image, on rendered synthetic chests."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.chest_plane import chest_forward
from hsr_handover.robot.perception.skeleton import lift_keypoints

CAMERA = PinholeCamera.from_fov_x(320, 240, 1.05)
# The head camera 1 m up, looking along world +x (camera x right = world -y, y down = -z).
X_WC = np.eye(4)
X_WC[:3, :3] = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]
X_WC[:3, 3] = [0.0, 0.0, 1.0]
CHEST = np.array([1.6, 0.0, 0.9])  # the chest's centre, 1.6 m in front of the camera
HALF_WIDTH, SHOULDER_Z, WAIST_Z = 0.17, 1.0, 0.6
R_SHOULDER, L_SHOULDER = keypoint_index("r_shoulder"), keypoint_index("l_shoulder")


def _facing(yaw_deg: float) -> np.ndarray:
    """The chest's outward normal: toward the camera (-x), turned by `yaw_deg`."""
    yaw = math.radians(yaw_deg)
    return np.array([-math.cos(yaw), -math.sin(yaw), 0.0])


def _rays() -> np.ndarray:
    """(H, W, 3) world directions of every pixel's ray, scaled to unit depth."""
    v, u = np.indices((CAMERA.height, CAMERA.width), dtype=float)
    camera = np.stack([(u - CAMERA.cx) / CAMERA.fx, (v - CAMERA.cy) / CAMERA.fy, np.ones_like(u)])
    return np.einsum("ij,jhw->hwi", X_WC[:3, :3], camera)


def _render(normal: np.ndarray) -> np.ndarray:
    """Depth (H, W) of a flat chest through CHEST with `normal`, HALF_WIDTH to each side and
    from WAIST_Z to SHOULDER_Z; nothing (inf) elsewhere."""
    rays, origin = _rays(), X_WC[:3, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = ((CHEST - origin) @ normal) / (rays @ normal)
    points = origin + depth[..., None] * rays
    lateral = np.cross([0.0, 0.0, 1.0], normal)
    across = (points - CHEST) @ lateral
    on_chest = (np.abs(across) < HALF_WIDTH) & (points[..., 2] > WAIST_Z)
    on_chest &= (points[..., 2] < SHOULDER_Z) & (depth > 0)
    return np.where(on_chest, depth, np.inf).astype(np.float32)


def _shoulder_pixels(normal: np.ndarray) -> np.ndarray:
    """(18, 2) pixels with the shoulders' at the chest's top corners, the rest undetected."""
    lateral = np.cross([0.0, 0.0, 1.0], normal)
    top = np.array([CHEST[0], CHEST[1], SHOULDER_Z])
    shoulders = np.array([top - HALF_WIDTH * lateral, top + HALF_WIDTH * lateral])
    pixels = np.full((NUM_KEYPOINTS, 2), np.nan)
    pixels[[R_SHOULDER, L_SHOULDER]] = CAMERA.project(shoulders, X_WC)[0]
    return pixels


def _shoulders_seen() -> np.ndarray:
    confidence = np.zeros(NUM_KEYPOINTS)
    confidence[[R_SHOULDER, L_SHOULDER]] = 1.0
    return confidence


def _yaw_deg(vector: np.ndarray) -> float:
    return math.degrees(math.atan2(vector[1], vector[0]))


@pytest.mark.parametrize("yaw_deg", [-30.0, -12.0, 0.0, 8.0, 25.0])
def test_the_chest_faces_where_the_person_is_turned(yaw_deg):
    normal = _facing(yaw_deg)
    facing = chest_forward(
        _render(normal), _shoulder_pixels(normal), _shoulders_seen(), CAMERA, X_WC
    )
    assert facing is not None and facing[2] == 0.0
    assert _yaw_deg(facing) == pytest.approx(_yaw_deg(normal), abs=0.5)


def test_a_plane_turned_far_from_the_camera_is_no_chest():
    """Fitted edge on (an arm hanging in front of the chest), a plane faces sideways."""
    normal = _facing(70.0)
    assert chest_forward(_render(normal), _shoulder_pixels(normal), _shoulders_seen(),
                         CAMERA, X_WC) is None  # fmt: skip


def _arm_far_in_front(depth: np.ndarray, pixels: np.ndarray) -> None:
    """A forearm 0.3 m nearer the camera, 12 px wide, down from between the shoulders."""
    middle = np.rint(pixels[[R_SHOULDER, L_SHOULDER]].mean(axis=0)).astype(int)
    depth[middle[1] :, middle[0] - 6 : middle[0] + 6] = 1.3


def _forearm_close_in_front(depth: np.ndarray, pixels: np.ndarray) -> None:
    """A forearm across a third of the patch, 8 cm in front of the chest's middle and square
    to the camera: a fit through both surfaces would turn the chest."""
    (right, row), (left, _) = np.rint(pixels[[R_SHOULDER, L_SHOULDER]]).astype(int)
    middle = depth[row + 20, (right + left) // 2]
    depth[:, right + (left - right) // 5 : right + 2 * (left - right) // 5] = middle - 0.08


@pytest.mark.parametrize(
    ("yaw_deg", "occlude"), [(20.0, _arm_far_in_front), (-15.0, _forearm_close_in_front)]
)
def test_an_arm_in_front_of_the_chest_is_left_out(yaw_deg, occlude):
    """The plane holding the most points is the chest's, not the arm's nor one through both."""
    normal = _facing(yaw_deg)
    depth, pixels = _render(normal), _shoulder_pixels(normal)
    occlude(depth, pixels)
    facing = chest_forward(depth, pixels, _shoulders_seen(), CAMERA, X_WC)
    assert facing is not None
    assert _yaw_deg(facing) == pytest.approx(_yaw_deg(normal), abs=1.0)


def test_no_direction_without_both_shoulders_or_without_a_chest():
    normal = _facing(10.0)
    depth, pixels = _render(normal), _shoulder_pixels(normal)
    one_shoulder = _shoulders_seen()
    one_shoulder[L_SHOULDER] = 0.0
    assert chest_forward(depth, pixels, one_shoulder, CAMERA, X_WC) is None
    nothing = np.full_like(depth, np.inf)
    assert chest_forward(nothing, pixels, _shoulders_seen(), CAMERA, X_WC) is None
    nan_depth = np.full_like(depth, np.nan)
    assert chest_forward(nan_depth, pixels, _shoulders_seen(), CAMERA, X_WC) is None


def test_the_same_frame_gives_the_same_facing():
    normal = _facing(12.0)
    depth, pixels = _render(normal), _shoulder_pixels(normal)
    depth += np.random.default_rng(1).normal(0.0, 0.004, depth.shape).astype(np.float32)
    first = chest_forward(depth, pixels, _shoulders_seen(), CAMERA, X_WC)
    np.testing.assert_array_equal(
        first, chest_forward(depth, pixels, _shoulders_seen(), CAMERA, X_WC)
    )
    assert _yaw_deg(first) == pytest.approx(_yaw_deg(normal), abs=2.0)  # with 4 mm depth noise


def test_the_lifted_skeleton_carries_the_chests_facing():
    normal = _facing(-18.0)
    skeleton = lift_keypoints(
        _shoulder_pixels(normal), _shoulders_seen(), _render(normal), CAMERA, X_WC
    )
    assert _yaw_deg(skeleton.torso_forward) == pytest.approx(_yaw_deg(normal), abs=0.5)
    unseen = lift_keypoints(
        _shoulder_pixels(normal), _shoulders_seen(), np.full((240, 320), np.inf), CAMERA, X_WC
    )
    assert np.isnan(unseen.torso_forward).all()
