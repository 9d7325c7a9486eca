"""Pinhole geometry agrees with Drake's camera model and inverts itself."""

from __future__ import annotations

import math

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.sensors import CameraInfo

from hsr_handover.interface.camera_info import to_camera_info
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.depth_view import DepthView
from hsr_handover.scenario import CameraConfig


def _pose() -> np.ndarray:
    return RigidTransform(RollPitchYaw(-1.7, 0.1, -1.5), [0.1, -0.2, 1.0]).GetAsMatrix4()


def test_intrinsics_match_drakes_camera_info():
    config = CameraConfig(width=640, height=480, fov_x=1.05)
    fov_y = 2.0 * math.atan(math.tan(config.fov_x / 2.0) * config.height / config.width)
    ours, drakes = config.pinhole(), CameraInfo(config.width, config.height, fov_y)
    assert (
        abs(to_camera_info(config.pinhole()).focal_y() - drakes.focal_y()) < 1e-9
    )  # what the renderer gets
    for mine, theirs in (
        (ours.fx, drakes.focal_x()),
        (ours.fy, drakes.focal_y()),
        (ours.cx, drakes.center_x()),
        (ours.cy, drakes.center_y()),
    ):
        assert abs(mine - theirs) < 1e-9


def test_project_then_deproject_returns_the_points():
    camera = PinholeCamera.from_fov_x(640, 480, 1.05)
    rng = np.random.default_rng(0)
    X_WC = _pose()
    points_C = np.column_stack(
        [rng.uniform(-0.5, 0.5, 100), rng.uniform(-0.4, 0.4, 100), rng.uniform(0.5, 3.0, 100)]
    )
    points_W = points_C @ X_WC[:3, :3].T + X_WC[:3, 3]
    pixels, depth = camera.project(points_W, X_WC)
    np.testing.assert_allclose(depth, points_C[:, 2])
    np.testing.assert_allclose(camera.deproject(pixels, depth, X_WC), points_W, atol=1e-12)


def test_deproject_image_keeps_pixel_order_and_marks_missing_depth():
    camera = PinholeCamera.from_fov_x(8, 6, 1.0)
    depth = np.full((6, 8), 2.0)
    depth[1, 3] = np.nan
    depth[4, 5] = np.inf
    points = camera.deproject_image(depth, np.eye(4))
    assert points.shape == (48, 3)
    assert np.isnan(points[1 * 8 + 3]).all() and np.isnan(points[4 * 8 + 5]).all()
    assert np.isfinite(points).all(axis=1).sum() == 46
    pixel = camera.project(points[2 * 8 + 6][None], np.eye(4))[0][0]
    np.testing.assert_allclose(pixel, [6, 2])


def test_scaled_camera_sees_the_same_ray():
    camera = PinholeCamera.from_fov_x(640, 480, 1.05)
    small = camera.scaled(200, 200)
    point = np.array([[0.3, -0.1, 1.7]])
    (u, v), _ = camera.project(point, np.eye(4))[0][0], None
    (us, vs) = small.project(point, np.eye(4))[0][0]
    np.testing.assert_allclose(
        [(us + 0.5) / 200, (vs + 0.5) / 200], [(u + 0.5) / 640, (v + 0.5) / 480]
    )
    assert camera.contains(np.array([[-0.4, 0.0], [639.4, 479.4]])).all()
    assert not camera.contains(np.array([[-0.6, 0.0], [0.0, 479.6]])).any()


def _looking_down(depth_value: float) -> tuple[PinholeCamera, np.ndarray, np.ndarray]:
    """A 40 x 30 camera 2 m up looking straight down over (1, 0), seeing a flat surface
    `depth_value` m away everywhere but its top-left quarter (0: too near to measure) and its
    bottom-right pixel (NaN)."""
    camera = PinholeCamera.from_fov_x(40, 30, 1.0)
    X_WC = RigidTransform(RollPitchYaw(math.pi, 0, 0), [1.0, 0.0, 2.0]).GetAsMatrix4()
    depth = np.full((30, 40), depth_value, np.float32)
    depth[:15, :20] = 0.0
    depth[-1, -1] = np.nan
    return camera, X_WC, depth


def test_depth_seen_reads_the_image_along_each_points_line_of_sight():
    camera, X_WC, depth = _looking_down(1.2)  # a floor at z = 0.8
    points = np.array([[1.0, 0.0, 1.5], [9.0, 0.0, 1.0], [1.0, 0.0, 2.5]])
    seen, point_depth, pixels = camera.depth_seen(depth, points, X_WC)
    np.testing.assert_allclose(point_depth[:2], [0.5, 1.0])
    assert point_depth[2] < 0  # behind the camera
    assert seen[0] == np.float32(1.2) and np.isnan(seen[1:]).all()  # out of view
    np.testing.assert_allclose(pixels[0], [camera.cx, camera.cy])


def test_a_depth_view_tells_hidden_from_empty_from_unknown():
    camera, X_WC, depth = _looking_down(1.2)
    view = DepthView(camera, X_WC, depth)
    below_left = camera.deproject(np.array([[2.0, 2.0]]), [1.0], X_WC)  # the 0-depth quarter
    last_pixel = camera.deproject(np.array([[39.0, 29.0]]), [1.0], X_WC)
    points = np.vstack([[1.0, 0.0, 1.5], [1.0, 0.0, 0.5], below_left, last_pixel,
                        [9.0, 0.0, 1.0]])  # fmt: skip
    past = view.depth_past(points)
    np.testing.assert_allclose(past[:2], [0.7, -0.3], atol=1e-6)  # empty above, hidden below
    assert np.isnan(past[2:]).all()  # too near to measure, no measurement, out of view
    depth[:] = np.inf  # nothing in range
    assert np.isposinf(DepthView(camera, X_WC, depth).depth_past(points[:1])).all()
