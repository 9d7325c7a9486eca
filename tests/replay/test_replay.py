"""Replay framing: the camera pose frame_view sets sees the whole scene box, large, and lands
in the static HTML."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.replay.meshcat_replay import (
    MIN_ASPECT,
    frame_view,
    framing_pose,
    make_local_meshcat,
    start_recording,
    write_replay,
)
from tests.meshcat_html import meshcat_commands

FOV_Y = np.radians(75.0)  # Meshcat's default perspective camera
# Robot base and head top, table corners, person's feet and head (demo.yaml's layout).
DEMO_POINTS = np.array(
    [[0, 0, 0], [0, 0, 1.35], [0.55, -0.5, 0], [1.15, 0.5, 0.72], [1.75, 0, 0], [1.75, 0, 1.7]]
)
SCENES = {
    "demo": (DEMO_POINTS, [0.0, 0.0]),
    "robot_on_the_left": (DEMO_POINTS[:, [1, 0, 2]] + [2.0, -1.0, 0.0], [2.0, -1.0]),
    "flat_and_wide": (np.array([[-3.0, -0.5, 0.0], [3.0, 0.5, 0.2]]), [0.0, -4.0]),
    "tall_and_thin": (np.array([[0.0, 0.0, 0.0], [0.2, 0.2, 2.5]]), [-1.0, 0.0]),
}


def corners(points: np.ndarray) -> np.ndarray:
    low, high = points.min(axis=0), points.max(axis=0)
    return np.array([[(high if i >> k & 1 else low)[k] for k in range(3)] for i in range(8)])


def image_coordinates(camera: np.ndarray, target: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Each point's (right, up) over depth, and its depth, for a camera looking at the target
    with the world's z up (as Meshcat orients it)."""
    forward = (target - camera) / np.linalg.norm(target - camera)
    right = np.cross(forward, [0, 0, 1])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rays = points - camera
    depth = rays @ forward
    return np.column_stack([rays @ right / depth, rays @ up / depth, depth])


@pytest.mark.parametrize("scene", SCENES)
def test_framing_keeps_the_box_in_view_and_large(scene: str) -> None:
    points, side = SCENES[scene]
    camera, target = framing_pose(points, side)
    seen = image_coordinates(camera, target, corners(points))
    half = np.tan(FOV_Y / 2) * np.array([MIN_ASPECT, 1.0])  # half-width, half-height
    assert np.all(seen[:, 2] > 0)
    assert np.all(np.abs(seen[:, :2]) <= half + 1e-9)
    # Fills at least half of the view along one axis (the other is set by the box's shape).
    span = (seen[:, :2].max(axis=0) - seen[:, :2].min(axis=0)) / (2 * half)
    assert span.max() >= 0.5


def test_framing_looks_from_the_side_and_above() -> None:
    camera, target = framing_pose(DEMO_POINTS, [0.0, 0.0])
    assert np.all(DEMO_POINTS.min(axis=0) <= target) and np.all(target <= DEMO_POINTS.max(axis=0))
    away = camera - target
    assert away[0] < 0 and away[1] > 0  # behind the robot, over its left (arm) shoulder
    assert np.degrees(np.arcsin(away[2] / np.linalg.norm(away))) == pytest.approx(30.0)


def test_frame_view_is_written_to_the_replay(tmp_path) -> None:
    meshcat = make_local_meshcat()
    start_recording(meshcat, 20.0)
    camera, target = frame_view(meshcat, DEMO_POINTS, [0.0, 0.0])
    html = write_replay(meshcat, tmp_path / "replay.html").read_text()
    commands = meshcat_commands(html)
    # three.js is y-up: Drake's (x, y, z) is (x, z, -y) there.
    position = [
        c["value"]
        for c in commands
        if c.get("path") == "/Cameras/default/rotated/<object>" and c.get("property") == "position"
    ]
    targets = [c["value"] for c in commands if c["type"] == "set_target"]
    np.testing.assert_allclose(position[-1], camera[[0, 2, 1]] * [1, 1, -1])
    np.testing.assert_allclose(targets[-1], target[[0, 2, 1]] * [1, 1, -1])
