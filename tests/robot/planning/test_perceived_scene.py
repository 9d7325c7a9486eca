"""What the planner avoids, from percepts (layer 1): object shapes from depth points, the
person's capsules from a lifted skeleton."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.robot.perception.object_shapes import (
    BOX,
    CYLINDER,
    MIN_POINTS,
    ONE_FACE,
    fit_shape,
)
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.perceived_scene import (
    BODY_COLUMN_RADIUS,
    BONES,
    HAND_LENGTH,
    ROBOT_KEEP,
    UNSEEN_EXTENSION,
    Capsule,
    extend_past_view,
    hidden_elbow,
    person_capsules,
)

TABLE_TOP = 0.72


def _cylinder_seen_from(camera_xy, center, radius, height, rng) -> np.ndarray:
    """The half of a cylinder's side that faces the camera, and its rim."""
    toward = math.atan2(camera_xy[1] - center[1], camera_xy[0] - center[0])
    side = rng.uniform(toward - math.pi / 2, toward + math.pi / 2, 600)
    rim = rng.uniform(0, 2 * math.pi, 200)
    angles = np.concatenate([side, rim])
    z = np.concatenate([rng.uniform(TABLE_TOP, TABLE_TOP + height, 600),
                        np.full(200, TABLE_TOP + height)])  # fmt: skip
    return np.column_stack([center[0] + radius * np.cos(angles),
                            center[1] + radius * np.sin(angles), z])  # fmt: skip


def test_a_cup_is_a_cylinder_of_its_size_though_only_its_front_and_rim_are_seen():
    points = _cylinder_seen_from((0, 0), (0.8, 0.2), 0.035, 0.1, np.random.default_rng(0))
    shape = fit_shape("red", points, TABLE_TOP)
    assert shape.kind == CYLINDER and shape.label == "red"
    np.testing.assert_allclose(shape.center, [0.8, 0.2], atol=2e-3)
    assert shape.radius == pytest.approx(0.035, abs=2e-3)
    assert shape.height == pytest.approx(0.1, abs=1e-6) and shape.bottom == TABLE_TOP
    np.testing.assert_allclose(shape.centroid, [0.8, 0.2, TABLE_TOP + 0.05], atol=2e-3)


def test_a_box_is_a_box_with_its_sides_and_yaw():
    rng = np.random.default_rng(1)
    local = np.column_stack([rng.uniform(-0.05, 0.05, 800), rng.uniform(-0.03, 0.03, 800)])
    yaw = 0.4
    rotation = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    xy = np.array([0.9, -0.1]) + local @ rotation.T
    points = np.column_stack([xy, np.full(800, TABLE_TOP + 0.12)])  # its lid
    shape = fit_shape("yellow", points, TABLE_TOP)
    assert shape.kind == BOX
    np.testing.assert_allclose(shape.center, [0.9, -0.1], atol=3e-3)
    sides = sorted(shape.size)
    assert sides == pytest.approx([0.06, 0.1], abs=4e-3)
    long_side_yaw = shape.yaw if shape.size[0] > shape.size[1] else shape.yaw + math.pi / 2
    assert math.sin(long_side_yaw - yaw) == pytest.approx(0.0, abs=0.03)
    assert shape.radius == pytest.approx(math.hypot(0.05, 0.03), abs=3e-3)


def _seen_level_with_its_top(points: np.ndarray, rng, noise: float = 0.0) -> np.ndarray:
    """`points` with the far two thirds of the top left out (a camera barely above it sees only
    the top's near edge) and, given `noise` (m), depth noise along the rays from a camera at
    the origin, 1 m up."""
    top = points[:, 2].max()
    far = (points[:, 2] > top - 1e-6) & (points[:, 0] > points[:, 0].min() + 0.02)
    points = points[~far]
    rays = points - [0.0, 0.0, TABLE_TOP + 0.25]
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    return points + rays * rng.normal(0.0, noise, (len(points), 1))


def _box_seen_from_the_origin(center, sides, yaw, height, rng) -> np.ndarray:
    """The two faces of an upright box (`sides` along its yaw and across) that face a camera at
    the origin, and its lid."""
    turn = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    a, b = np.asarray(sides) / 2
    faces = []
    for normal, half, other in (([1, 0], b, a), ([0, 1], a, b)):
        for sign in (-1, 1):
            outward = turn @ (sign * np.asarray(normal, float))
            if outward @ (np.zeros(2) - center) <= 0:
                continue
            along = rng.uniform(-half, half, 400)
            local = sign * other * np.asarray(normal, float) + np.outer(along, normal[::-1])
            heights = rng.uniform(TABLE_TOP, TABLE_TOP + height, 400)
            faces.append(np.column_stack([center + local @ turn.T, heights]))
    lid = rng.uniform([-a, -b], [a, b], (300, 2))
    faces.append(np.column_stack([center + lid @ turn.T, np.full(300, TABLE_TOP + height)]))
    return np.vstack(faces)


@pytest.mark.parametrize("noise", [0.0, 0.0015])
def test_a_cup_seen_level_with_its_rim_is_a_cylinder_of_its_size(noise):
    """The front of a cup is an arc whose smallest rectangle is tighter than its circle: its
    footprint alone reads it as a box. Its side's arc names it, with a depth camera's noise
    (1.5 mm at 1 m) too."""
    rng = np.random.default_rng(2)
    cup = _cylinder_seen_from((0, 0), (0.8, 0.2), 0.035, 0.1, rng)
    shape = fit_shape("red", _seen_level_with_its_top(cup, rng, noise), TABLE_TOP)
    assert shape.kind == CYLINDER
    np.testing.assert_allclose(shape.center, [0.8, 0.2], atol=2e-3 + 2 * noise)
    assert shape.radius == pytest.approx(0.035, abs=1e-3 + 2 * noise)


@pytest.mark.parametrize("noise", [0.0, 0.0015])
def test_a_box_seen_corner_on_and_level_with_its_lid_is_a_box_turned_as_its_faces(noise):
    """The smallest rectangle around two faces seen corner on lies along their diagonal; the
    box is turned as its faces are."""
    rng = np.random.default_rng(3)
    center, yaw = np.array([0.85, -0.15]), math.atan2(-0.15, 0.85) + math.radians(45.0)
    box = _box_seen_from_the_origin(center, (0.07, 0.06), yaw, 0.11, rng)
    shape = fit_shape("blue", _seen_level_with_its_top(box, rng, noise), TABLE_TOP)
    assert shape.kind == BOX
    turned = shape.yaw if shape.size[0] > shape.size[1] else shape.yaw + math.pi / 2
    assert math.sin(turned - yaw) == pytest.approx(0.0, abs=0.05)
    assert sorted(shape.size) == pytest.approx([0.06, 0.07], abs=2e-3 + 4 * noise)
    np.testing.assert_allclose(shape.center, center, atol=2e-3 + 2 * noise)


@pytest.mark.parametrize("noise", [0.0, 0.0015])
def test_a_box_seen_by_its_front_face_alone_is_as_deep_as_wide_behind_that_face(noise):
    """A camera level with the lid sees one face: the box is taken as deep as the face is wide,
    on the face's far side from the camera, not as a sheet standing on the face."""
    rng = np.random.default_rng(4)
    center, width, depth = np.array([0.9, -0.3]), 0.064, 0.057
    toward = -center / np.linalg.norm(center)  # the face's normal, toward the camera
    along = np.array([-toward[1], toward[0]])
    face = center + toward * depth / 2 + np.outer(rng.uniform(-width / 2, width / 2, 500), along)
    points = np.column_stack([face, rng.uniform(TABLE_TOP, TABLE_TOP + 0.11, 500)])
    points = _seen_level_with_its_top(points, rng, noise)
    sheet = fit_shape("cyan", points, TABLE_TOP)
    assert sheet.kind == BOX and min(sheet.size) < ONE_FACE
    shape = fit_shape("cyan", points, TABLE_TOP, viewpoint=np.zeros(2))
    assert shape.kind == BOX
    assert sorted(shape.size) == pytest.approx([width, width], abs=2e-3 + 4 * noise)
    np.testing.assert_allclose(shape.center, center, atol=depth / 2 - width / 2 + 0.01)
    assert np.linalg.norm(shape.center) > np.linalg.norm(sheet.center) + 0.02  # behind the face


def test_a_box_showing_its_depth_keeps_its_size_with_the_camera_known():
    rng = np.random.default_rng(3)
    center, yaw = np.array([0.85, -0.15]), math.atan2(-0.15, 0.85) + math.radians(45.0)
    points = _box_seen_from_the_origin(center, (0.07, 0.06), yaw, 0.11, rng)
    seen = fit_shape("blue", points, TABLE_TOP)
    known = fit_shape("blue", points, TABLE_TOP, viewpoint=np.zeros(2))
    np.testing.assert_allclose(known.size, seen.size)
    np.testing.assert_allclose(known.center, seen.center)


def test_too_few_points_make_no_shape():
    points = np.full((MIN_POINTS - 1, 3), [0.8, 0.0, 0.8])
    assert fit_shape("red", points, TABLE_TOP) is None


def test_a_capsule_measures_distance_to_its_surface():
    capsule = Capsule(np.zeros(3), np.array([1.0, 0, 0]), 0.1)
    distances = capsule.distance(np.array([[0.5, 0.3, 0], [-0.2, 0, 0], [0.5, 0, 0]]))
    np.testing.assert_allclose(distances, [0.2, 0.1, -0.1])
    assert capsule.length == 1.0


def _skeleton() -> tuple[np.ndarray, np.ndarray]:
    """A person 2 m in front of a camera at the origin, facing it, the right arm held out."""
    points = np.full((NUM_KEYPOINTS, 3), np.nan)
    where = {"nose": (2.0, 0, 1.5), "neck": (2.0, 0, 1.35), "r_shoulder": (2.0, -0.2, 1.35),
             "r_elbow": (1.75, -0.2, 1.35), "r_wrist": (1.5, -0.2, 1.35),
             "l_shoulder": (2.0, 0.2, 1.35), "r_hip": (2.0, -0.1, 0.9)}  # fmt: skip
    for name, point in where.items():
        points[keypoint_index(name)] = point
    confidence = np.where(np.isfinite(points[:, 0]), 0.9, 0.0)
    return points, confidence


def test_the_person_is_capsules_behind_the_seen_surface_with_a_hand_past_the_wrist():
    points, confidence = _skeleton()
    camera = np.zeros(3)
    capsules = person_capsules(points, confidence, camera, margin=0.05)
    seen = [(a, b) for a, b in BONES if confidence[a] > 0 and confidence[b] > 0]
    *bones, column = capsules
    assert len(bones) == len(seen) == 6  # none to the left elbow or the left hip
    # The unseen body and seat: a column from the floor to the neck, set back from it.
    np.testing.assert_allclose(column.start[:2], [2.0 + BODY_COLUMN_RADIUS, 0], atol=1e-9)
    assert column.start[2] == column.radius == BODY_COLUMN_RADIUS + 0.05
    assert column.end[2] == pytest.approx(1.35)
    neck_to_shoulder = capsules[seen.index((keypoint_index("neck"), keypoint_index("r_shoulder")))]
    radius = BONES[keypoint_index("neck"), keypoint_index("r_shoulder")]
    assert neck_to_shoulder.radius == pytest.approx(radius + 0.05)
    # The axis lies a bone's radius behind the surface point, away from the camera.
    expected = points[keypoint_index("neck")] * (1 + radius / np.linalg.norm(points[1]))
    np.testing.assert_allclose(neck_to_shoulder.start, expected)
    forearm = capsules[seen.index((keypoint_index("r_elbow"), keypoint_index("r_wrist")))]
    bone = forearm.radius - 0.05
    assert forearm.length == pytest.approx(0.25 + HAND_LENGTH - bone, abs=0.01)
    fingertips = np.array([1.5 - HAND_LENGTH + 0.02, -0.2, 1.35])
    assert forearm.distance(fingertips)[0] < 0  # the hand is covered
    assert person_capsules(points, np.zeros(NUM_KEYPOINTS), camera) == ()


def test_the_hand_ends_at_the_fingertips_widened_by_the_margin_only():
    """Seen from above: the forearm's capsule reaches a hand's length past the wrist plus the
    margin, not a bone's radius more (its round end is the hand's end)."""
    points, confidence = _skeleton()
    wrist = points[keypoint_index("r_wrist")]
    capsules = person_capsules(points, confidence, wrist + [0.0, 0.0, 1.0], margin=0.05)
    (forearm,) = (capsule for capsule in capsules if capsule.part == "r_elbow-r_wrist")
    bone = forearm.radius - 0.05
    axis_past_wrist = wrist - [0.0, 0.0, bone] - [HAND_LENGTH + 0.05, 0.0, 0.0]
    np.testing.assert_allclose(forearm.distance(axis_past_wrist), 0.0, atol=1e-3)
    assert forearm.distance(axis_past_wrist - [0.01, 0.0, 0.0])[0] > 0.009


def test_a_hidden_elbow_hangs_below_the_line_from_shoulder_to_wrist():
    shoulder, wrist = np.array([2.0, -0.2, 1.35]), np.array([1.6, -0.2, 1.0])
    elbow = hidden_elbow(shoulder, wrist, 0.3, 0.25)
    assert np.linalg.norm(elbow - shoulder) == pytest.approx(0.3)
    assert np.linalg.norm(wrist - elbow) == pytest.approx(0.25)
    assert elbow[1] == pytest.approx(-0.2)  # in the vertical plane through both
    line_at_elbow = np.interp(elbow[0], [wrist[0], shoulder[0]], [wrist[2], shoulder[2]])
    assert elbow[2] < line_at_elbow - 0.05
    # Out of the arm's reach: straight, in proportion.
    far = np.array([1.3, -0.2, 1.35])
    np.testing.assert_allclose(
        hidden_elbow(shoulder, far, 0.3, 0.25), [2.0 - 0.7 * 0.3 / 0.55, -0.2, 1.35]
    )
    # Straight down: the elbow on the line.
    below = np.array([2.0, -0.2, 0.85])
    np.testing.assert_allclose(hidden_elbow(shoulder, below, 0.3, 0.25)[:2], [2.0, -0.2])


def test_an_arm_whose_elbow_is_hidden_keeps_its_capsules():
    points, confidence = _skeleton()
    camera = np.zeros(3)
    seen_whole = person_capsules(points, confidence, camera)
    confidence[keypoint_index("r_elbow")] = 0.0  # the robot's arm in front of it
    hidden = person_capsules(points, confidence, camera)
    assert len(hidden) == len(seen_whole)
    hand = np.array([[1.5 - HAND_LENGTH + 0.03, -0.2, 1.35], [1.75, -0.2, 1.35]])
    assert (np.min([capsule.distance(hand) for capsule in hidden], axis=0) < 0).all()
    # A hidden shoulder is mirrored through the neck; without it and the neck there are no
    # proportions to go by, and the arm stays unseen.
    confidence[keypoint_index("l_shoulder")] = 0.0
    mirrored = person_capsules(points, confidence, camera)
    assert (np.min([capsule.distance(hand) for capsule in mirrored], axis=0) < 0).all()
    confidence[keypoint_index("neck")] = 0.0
    unseen = {capsule.part for capsule in person_capsules(points, confidence, camera)}
    assert not unseen & {"r_shoulder-r_elbow", "r_elbow-r_wrist"}


def test_a_hip_lifted_over_the_table_draws_no_torso_across_it():
    """A seated person's hip just visible over the table's far edge, its pixel a few off, is
    lifted onto the edge or an object in front of the body; a hip below the top, behind the
    edge, is the person's."""
    points, confidence = _skeleton()
    table = TableEstimate(0.8, np.array([1.5, 0.0]), np.array([1.0, 0.6]), math.pi / 2, 3000)
    camera = np.zeros(3)
    hip = keypoint_index("r_hip")

    def parts():
        return {c.part for c in person_capsules(points, confidence, camera, table=table)}

    assert "neck-r_hip" in parts()  # (2.0, -0.1, 0.9): 20 cm behind the far edge
    points[hip] = (1.78, -0.1, 0.82)  # on the far edge's top, 2 cm in
    assert "neck-r_hip" not in parts()
    assert "neck-r_hip" in {c.part for c in person_capsules(points, confidence, camera)}
    points[hip] = (1.6, -0.1, 0.9)  # on a box on the table
    assert "neck-r_hip" not in parts()
    points[hip] = (1.85, -0.1, 0.6)  # below the top, past the edge: a seated hip
    assert "neck-r_hip" in parts()
    points[hip] = (1.6, -0.1, 0.7)  # under the top, as a seated person's knee is
    assert "neck-r_hip" in parts()


def test_open_edges_run_on_unseen_but_never_under_the_robot():
    table = TableEstimate(TABLE_TOP, np.array([1.0, 0.0]), np.array([0.3, 1.0]), 0.0, 3000)
    np.testing.assert_allclose(extend_past_view(table, np.zeros(2)).size, table.size)
    # Both ends open: each runs on by UNSEEN_EXTENSION.
    ends = dataclasses.replace(table, open_edges=(False, False, True, True))
    extended = extend_past_view(ends, np.zeros(2))
    np.testing.assert_allclose(extended.size, [0.3, 1.0 + 2 * UNSEEN_EXTENSION])
    np.testing.assert_allclose(extended.center, table.center)
    # The near edge open (the head raised): it stops ROBOT_KEEP short of the camera at x = 0.
    near = dataclasses.replace(table, open_edges=(False, True, False, False))
    pushed = extend_past_view(near, np.zeros(2))
    assert pushed.center[0] - pushed.size[0] / 2 == pytest.approx(ROBOT_KEEP)
    assert pushed.center[0] + pushed.size[0] / 2 == pytest.approx(1.15)
