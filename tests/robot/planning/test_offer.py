"""offer_points: where an object is held out at a waiting hand, clear of the person's capsules."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.planning.inverse_kinematics import MIN_DISTANCE
from hsr_handover.robot.planning.offer import (
    FINGERS_EXTENT,
    OFFER_OFFSETS,
    OFFER_SEARCH,
    OFFER_TRIES,
    object_extent,
    offer_points,
)
from hsr_handover.robot.planning.perceived_scene import Capsule

AIM = np.array([1.2, 0.2, 0.9])
CUP = ObjectShape("blue", CYLINDER, np.array([1.2, 0.2]), np.array([0.08, 0.08]), 0.0, 0.72, 0.09)
# A forearm held out toward the robot, its capsule running on past the wrist over the aim
FOREARM = Capsule(AIM + [0.4, 0.0, 0.0], AIM - [0.05, 0.0, 0.0], 0.095)


def test_with_no_person_perceived_the_aim_itself_is_offered():
    points = offer_points(AIM, (), object_extent(CUP))
    assert len(points) == 1
    np.testing.assert_array_equal(points[0], AIM)


def test_an_aim_inside_the_forearm_moves_to_the_nearest_point_clear_of_it():
    extent = object_extent(CUP)
    points = offer_points(AIM, (FOREARM,), extent)
    assert 0 < len(points) <= OFFER_TRIES
    needed = extent + MIN_DISTANCE
    for point in points:
        assert FOREARM.distance(point)[0] >= needed
        assert np.linalg.norm(point - AIM) <= OFFER_SEARCH + 1e-9
    # the nearest: no point of the lattice nearer the aim fits
    nearest = float(np.linalg.norm(points[0] - AIM))
    inside = AIM + OFFER_OFFSETS[np.linalg.norm(OFFER_OFFSETS, axis=1) < nearest - 1e-9]
    assert (FOREARM.distance(inside) < needed).all()
    # square to the forearm, over it rather than under it
    assert points[0][2] > AIM[2]


def test_an_aim_buried_in_the_person_offers_nothing():
    body = Capsule(AIM - [0.0, 0.0, 1.0], AIM + [0.0, 0.0, 1.0], 0.3)
    assert offer_points(AIM, (body,), object_extent(CUP)) == []


def test_an_objects_extent_covers_its_widened_solid():
    extent = object_extent(CUP)
    assert extent > np.hypot(0.04, 0.045)
    assert object_extent(None) == FINGERS_EXTENT  # the hand alone still needs room
