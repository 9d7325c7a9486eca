"""How near a path comes to the person as perceived: what a carry under way is checked by."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.robot.planning.planner import Held, person_clearance
from hsr_handover.robot.planning.planning_scene import PERSON, PlanningScene

PERSON_X = 1.6  # m ahead of the base: the person's axis
PERSON_RADIUS = 0.2


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    body = Capsule(np.array([PERSON_X, 0.0, 0.2]), np.array([PERSON_X, 0.0, 1.4]), PERSON_RADIUS)
    return PlanningScene(PerceivedScene(None, (), (body,)))


def _driven(scene: PlanningScene, xs) -> list[np.ndarray]:
    """The HSR at rest with its base driven to each of `xs` (m)."""
    path = []
    for x in xs:
        scene.set_positions({"base_x_joint": x})
        path.append(scene.positions())
    return path


def test_a_path_into_the_person_comes_inside_and_one_short_of_them_does_not(scene):
    short = _driven(scene, np.linspace(0.0, 0.8, 9))
    assert person_clearance(scene, short, within=0.0) == math.inf
    nearest = person_clearance(scene, short)
    assert nearest == pytest.approx(scene.clearances_at(short[-1])[PERSON])
    assert 0.0 < nearest < PERSON_X - PERSON_RADIUS - 0.8
    into = [*short, *_driven(scene, [1.3])]
    assert person_clearance(scene, into, within=0.0) < 0.0


def test_an_empty_path_keeps_clear(scene):
    assert person_clearance(scene, []) == math.inf


def test_the_object_held_counts_as_the_hand_does(scene):
    """A cup in the hand, held out toward the person, comes nearer them than the hand alone."""
    (q,) = _driven(scene, [0.75])
    pads = scene.hand_pose(q).translation()
    cup = ObjectShape("red", CYLINDER, pads[:2], np.array([0.07, 0.07]), 0.0, pads[2] - 0.05, 0.1)
    perceived = PerceivedScene(None, (cup,), scene.scene.person)
    held_scene = PlanningScene(perceived)
    hand_only = person_clearance(held_scene, [q], None, within=1.0)
    holding = person_clearance(held_scene, [q], Held("red", q, cup), within=1.0)
    assert holding < hand_only - 0.01
