"""Where the robot watches from: the camera raised until the objects cannot hide a pointing arm,
and the arm folded out of the camera's view."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import CAMERA_FRAME, TORSO_JOINT
from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.handover.watch_view import (
    EYES_OVER_SHOULDERS,
    FLEX,
    LEAST_RISE,
    LIFT,
    POINTING_REACH,
    SHOULDER_DEPTH,
    camera_rise,
    plausible_shoulders,
    reach_points,
    watch_posture,
    weigh_now,
)
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.robot.perception.torso_depth import seen_shoulders
from hsr_handover.robot.planning.perceived_scene import PerceivedScene, behind
from hsr_handover.robot.planning.planning_scene import PlanningScene

SHOULDERS = [np.array([1.74, -0.03, 0.99]), np.array([1.66, -0.36, 0.99])]  # 1.58 m, seated
TALLER = [shoulder + [0.0, 0.0, 0.04] for shoulder in SHOULDERS]  # 1.70 m, seated
CAMERA = PinholeCamera.from_fov_x(320, 240, 1.05)  # the scenarios' head camera


def _objects(table: float) -> list[ObjectShape]:
    """Two cups and a box standing on a table `table` m high, 0.8-0.95 m from the robot."""
    placed = (("red", CYLINDER, 0.78, -0.30, 0.07, 0.10), ("yellow", BOX, 0.92, -0.08, 0.06, 0.12),
              ("green", CYLINDER, 0.80, 0.14, 0.07, 0.10))  # fmt: skip
    return [
        ObjectShape(label, kind, np.array([x, y]), np.array([side, side]), 0.0, table, height)
        for label, kind, x, y, side, height in placed
    ]


@pytest.fixture(scope="module")
def robot() -> PlanningScene:
    return PlanningScene(PerceivedScene(None))


def _ready(robot: PlanningScene) -> np.ndarray:
    robot.set_positions({"wrist_flex_joint": -1.57, "head_tilt_joint": -0.1})
    return robot.positions()


def _camera_pose(robot: PlanningScene, q: np.ndarray):
    robot.plant.SetPositions(robot.plant_context, q)
    return robot.plant.GetFrameByName(CAMERA_FRAME).CalcPoseInWorld(robot.plant_context)


def test_the_reach_points_lie_on_the_way_from_each_shoulder_to_each_object():
    objects = _objects(0.80)
    points = reach_points(SHOULDERS, objects)
    assert points.shape == (2 * len(SHOULDERS) * len(objects), 3)
    wrist = points[1]  # the first shoulder's wrist pointing at the first object
    assert np.linalg.norm(wrist - SHOULDERS[0]) == pytest.approx(POINTING_REACH)
    standing = np.array([*objects[0].center, objects[0].bottom])
    to_object = (standing - SHOULDERS[0]) / np.linalg.norm(standing - SHOULDERS[0])
    np.testing.assert_allclose((wrist - SHOULDERS[0]) / POINTING_REACH, to_object, atol=1e-12)


def test_objects_on_a_low_table_ask_for_no_rise(robot):
    camera = _camera_pose(robot, _ready(robot)).translation()
    assert camera_rise(camera, TALLER, _objects(0.72)) == 0.0
    assert watch_posture(robot, _ready(robot), TALLER, _objects(0.72)) is None
    assert camera_rise(camera, TALLER, _objects(0.80)) > 0.0  # the same person, a higher table


def test_a_camera_raised_by_the_rise_sees_over_every_object(robot):
    camera = _camera_pose(robot, _ready(robot)).translation()
    objects = _objects(0.80)
    rise = camera_rise(camera, SHOULDERS, objects)
    assert 0.05 < rise < 0.3
    assert camera_rise(camera + [0, 0, rise], SHOULDERS, objects) == pytest.approx(0.0, abs=1e-9)
    assert camera_rise(camera + [0, 0, rise - 0.01], SHOULDERS, objects) > 0.0


def test_an_object_beside_every_sight_line_asks_nothing(robot):
    camera = _camera_pose(robot, _ready(robot)).translation()
    objects = _objects(0.80)
    aside = ObjectShape("tall", BOX, np.array([0.9, 1.5]), np.array([0.1, 0.1]), 0.0, 0.8, 0.6)
    # Its own reach points are added, so compare with a low object at the same place.
    low = ObjectShape("low", BOX, np.array([0.9, 1.5]), np.array([0.1, 0.1]), 0.0, 0.8, 0.01)
    assert camera_rise(camera, SHOULDERS, [*objects, aside]) == pytest.approx(
        camera_rise(camera, SHOULDERS, [*objects, low])
    )


def _joints(shoulders: list[np.ndarray], camera: np.ndarray) -> list[np.ndarray]:
    return [behind(shoulder, camera, SHOULDER_DEPTH) for shoulder in shoulders]


def test_the_posture_raises_the_torso_by_the_rise_with_the_arm_folded_down(robot):
    q = _ready(robot)
    objects = _objects(0.80)
    camera = _camera_pose(robot, q).translation()
    rise = camera_rise(camera, _joints(SHOULDERS, camera), objects)
    assert rise < camera_rise(camera, SHOULDERS, objects)  # the joints are farther off
    raised = watch_posture(robot, q, SHOULDERS, objects)
    assert raised[robot.index(LIFT)] == pytest.approx(2 * rise)
    assert raised[robot.index(TORSO_JOINT)] == pytest.approx(rise)
    assert raised[robot.index(FLEX)] == robot.plant.GetPositionLowerLimits()[robot.index(FLEX)]
    camera = _camera_pose(robot, raised).translation()
    # From higher, the sight lines to the shoulders are steeper and put their joints a little
    # lower: the view asks for a few mm more, under LEAST_RISE.
    assert camera_rise(camera, _joints(SHOULDERS, camera), objects) < LEAST_RISE / 2
    assert watch_posture(robot, raised, SHOULDERS, objects) is None  # nothing more to rise for


def _arm_pixels_in_view(robot: PlanningScene, q: np.ndarray) -> int:
    """How many of the arm's links' origins and the hand's appear in the camera's image."""
    plant, context = robot.plant, robot.plant_context
    X_WC = _camera_pose(robot, q).GetAsMatrix4()
    names = ("arm_flex_link", "arm_roll_link", "wrist_flex_link", "wrist_roll_link",
             "hand_palm_link")  # fmt: skip
    points = np.array(
        [
            plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(name)).translation()
            for name in names
        ]  # fmt: skip
    )
    pixels, depth = CAMERA.project(points, X_WC)
    return int(np.sum(CAMERA.contains(pixels) & (depth > 0)))


def test_folded_the_arm_is_out_of_the_cameras_view_where_upright_it_is_not(robot):
    raised = watch_posture(robot, _ready(robot), SHOULDERS, _objects(0.80))
    assert _arm_pixels_in_view(robot, raised) == 0
    upright = raised.copy()
    upright[robot.index(FLEX)] = 0.0
    assert _arm_pixels_in_view(robot, upright) > 0


@pytest.mark.parametrize(
    ("other", "plausible"),
    [
        ([1.66, -0.36, 0.99], True),  # a short person's, 34 cm apart
        ([1.06, -0.08, 1.03], False),  # lifted onto the pointing arm: 66 cm off (reference 45)
        ([1.74, -0.12, 0.99], False),  # 9 cm apart
        ([1.66, -0.36, 0.79], False),  # 20 cm lower
    ],
)
def test_shoulders_that_could_not_be_one_persons_ask_for_nothing(robot, other, plausible):
    shoulders = [SHOULDERS[0], np.array(other)]
    assert plausible_shoulders(shoulders) is plausible
    posture = watch_posture(robot, _ready(robot), shoulders, _objects(0.80))
    assert (posture is not None) is plausible


def _skeleton(**points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lifted keypoints (18 x 3, 18 confidences) with only the named ones seen."""
    lifted, confidence = np.full((18, 3), np.nan), np.zeros(18)
    for name, point in points.items():
        lifted[keypoint_index(name)], confidence[keypoint_index(name)] = point, 0.9
    return lifted, confidence


def test_a_shoulder_hidden_behind_the_objects_is_mirrored_through_the_neck():
    neck = (SHOULDERS[0] + SHOULDERS[1]) / 2
    both = seen_shoulders(*_skeleton(r_shoulder=SHOULDERS[0], l_shoulder=SHOULDERS[1]))
    np.testing.assert_allclose(both, SHOULDERS)
    one = seen_shoulders(*_skeleton(r_shoulder=SHOULDERS[0], neck=neck))
    np.testing.assert_allclose(one, SHOULDERS)
    other = seen_shoulders(*_skeleton(l_shoulder=SHOULDERS[1], neck=neck))
    np.testing.assert_allclose(other, SHOULDERS)
    right, left = seen_shoulders(*_skeleton(r_shoulder=SHOULDERS[0]))  # no neck: no mirror
    assert left is None and right is not None


def test_the_view_is_weighed_first_with_both_shoulders_then_again_for_each_new_object():
    objects = _objects(0.80)
    assert weigh_now(None, *_skeleton(r_shoulder=SHOULDERS[0]), objects) is None
    assert weigh_now(None, *_skeleton(r_shoulder=SHOULDERS[0], l_shoulder=SHOULDERS[1]), []) is None
    first = weigh_now(None, *_skeleton(r_shoulder=SHOULDERS[0], l_shoulder=SHOULDERS[1]),
                      objects[:2])  # fmt: skip
    assert first.labels == {"red", "yellow"}
    leaning = _skeleton(r_shoulder=SHOULDERS[0] + 0.1, l_shoulder=SHOULDERS[1])
    assert weigh_now(first, *leaning, objects[:2]) is None  # nothing new
    again = weigh_now(first, *leaning, objects)
    assert again.labels == {"red", "yellow", "green"}
    np.testing.assert_allclose(again.shoulders, SHOULDERS)  # as first seen


def test_the_camera_rises_no_higher_than_the_persons_eyes(robot):
    q = _ready(robot)
    low = [shoulder - [0.0, 0.0, 0.12] for shoulder in SHOULDERS]  # a short person, seated
    objects = _objects(0.86)
    camera = _camera_pose(robot, q).translation()
    eyes = np.mean([shoulder[2] for shoulder in low]) + EYES_OVER_SHOULDERS
    assert camera[2] + camera_rise(camera, _joints(low, camera), objects) > eyes  # asked for
    raised = watch_posture(robot, q, low, objects)
    assert _camera_pose(robot, raised).translation()[2] == pytest.approx(eyes, abs=0.01)
