"""The planning scene: a plant of its own built from a PerceivedScene."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.robot.planning.planning_scene import (
    HELD,
    HELD_MARGIN,
    HELD_SPREAD,
    NEAR,
    OBJECT_MARGIN,
    PERSON,
    TABLE,
    TABLE_MARGIN,
    PlanningScene,
)

TABLE_TOP = 0.72
TABLE_NEAR_EDGE = 0.6  # m ahead of the robot's base


def _table() -> TableEstimate:
    size = np.array([0.6, 1.0])
    center = np.array([TABLE_NEAR_EDGE + size[0] / 2, 0.0])
    return TableEstimate(TABLE_TOP, center, size, 0.0, 6000)


def _cup(label: str, x: float, y: float) -> ObjectShape:
    return ObjectShape(label, CYLINDER, np.array([x, y]), np.array([0.07, 0.07]), 0.0,
                       TABLE_TOP, 0.1)  # fmt: skip


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    person = Capsule(np.array([1.6, 0.0, 0.8]), np.array([1.6, 0.0, 1.4]), 0.2)
    perceived = PerceivedScene(_table(), (_cup("red", 0.7, 0.2),), (person,))
    return PlanningScene(perceived)


def test_every_percept_becomes_named_collision_geometry(scene):
    assert set(scene.geometry) == {TABLE, "red", PERSON}
    inspector = scene.query().inspector()
    (table,) = scene.geometry[TABLE]
    margin = TABLE_MARGIN
    size = [0.6 + 2 * margin, 1.0 + 2 * margin, TABLE_TOP + margin]
    np.testing.assert_allclose(inspector.GetShape(table).size(), size)
    # The block stands on the floor: its top is the table's top, and a margin.
    center = inspector.GetPoseInFrame(table).translation()[2]
    assert center == pytest.approx((TABLE_TOP + margin) / 2)
    (cup,) = scene.geometry["red"]
    assert inspector.GetShape(cup).radius() == pytest.approx(0.035 + OBJECT_MARGIN)
    assert inspector.GetShape(cup).length() == pytest.approx(0.10 + OBJECT_MARGIN)


def test_clearance_follows_the_base_toward_the_table(scene):
    scene.set_positions({})
    far, nearest = scene.clearance(ignore=("red",))
    assert nearest == TABLE and 0.05 < far < TABLE_NEAR_EDGE
    scene.set_positions({"base_x_joint": 0.05})
    closer, _ = scene.clearance(ignore=("red",))
    assert closer == pytest.approx(far - 0.05, abs=2e-3)
    scene.set_positions({"base_x_joint": far + 0.05})
    inside, nearest = scene.clearance(ignore=("red",))
    assert nearest == TABLE and inside < 0  # penetration is a negative distance


def test_ignoring_an_obstacle_leaves_the_others():
    # A cup on the floor just ahead of the base is nearer than the table, until it is ignored
    # (as the target of a grasp is).
    cup = dataclasses.replace(_cup("red", 0.35, 0.0), bottom=0.0)
    scene = PlanningScene(PerceivedScene(_table(), (cup,)))
    scene.set_positions({})
    distance, nearest = scene.clearance()
    ignored_distance, other = scene.clearance(ignore=("red",))
    assert nearest == "red" and other == TABLE and ignored_distance > distance


def test_an_empty_scene_has_nothing_near():
    scene = PlanningScene(PerceivedScene(None))
    scene.set_positions({})
    assert scene.clearance() == (np.inf, "")


def test_a_held_object_moves_with_the_hand_and_keeps_its_distance():
    """A cup taken where it stands (the hand's pose at the grasp fixes where it sits in the
    hand), then lifted 10 cm: held, its bottom is 10 cm over the table, widened underneath by
    HELD_SPREAD, nearer than the hand; its copy on the table is gone; after the block, the
    scene is as it was."""
    cup = _cup("red", 0.7, 0.0)
    scene = PlanningScene(PerceivedScene(_table(), (cup,)))
    scene.set_positions({"arm_lift_joint": 0.2})
    q_grasp = scene.positions()
    scene.set_positions({"arm_lift_joint": 0.3})  # the whole hand 10 cm higher
    q_lifted = scene.positions()
    hand_only = scene.clearance_at(q_lifted, ignore=("red",))
    with scene.holding("red", q_grasp):
        assert HELD in scene.geometry
        held = scene.clearance_at(q_lifted)
        assert held == pytest.approx(0.10 - TABLE_MARGIN - HELD_SPREAD, abs=2e-3)
        assert held < hand_only
        assert scene.clearance_at(q_grasp) < 0  # put back where it stood: on the table's top
    assert HELD not in scene.geometry
    assert scene.clearance_at(q_lifted, ignore=("red",)) == pytest.approx(hand_only)


def test_a_held_object_is_widened_by_the_grips_margin():
    """Held where it stood, a cup 20 cm beside another is HELD_MARGIN nearer to it than two
    standing cups are: the sides of both are widened by OBJECT_MARGIN, the held one's by
    HELD_MARGIN more."""
    held, neighbour = _cup("red", 0.7, 0.0), _cup("blue", 0.7, 0.2)
    scene = PlanningScene(PerceivedScene(_table(), (held, neighbour)))
    scene.set_positions({"arm_lift_joint": 0.2})
    q_grasp = scene.positions()
    gap = 0.2 - 2 * (0.035 + OBJECT_MARGIN)
    with scene.holding("red", q_grasp):
        pairs = scene.query().ComputeSignedDistancePairwiseClosestPoints(0.5)
        (held_id,) = scene.geometry[HELD]
        (blue_id,) = scene.geometry["blue"]
        pair = [p for p in pairs if {p.id_A, p.id_B} == {held_id, blue_id}]
        assert pair[0].distance == pytest.approx(gap - HELD_MARGIN, abs=1e-3)


def test_an_object_held_is_placed_by_its_shape_when_grasped_not_as_seen_since():
    """Carried off, the cup is seen elsewhere as a column from the table up to its top, or not
    at all; held by its shape at the grasp, it hangs on the hand as it was grasped."""
    cup = _cup("red", 0.7, 0.0)
    moved = dataclasses.replace(cup, center=np.array([0.9, 0.1]), height=cup.height + 0.1)
    clearances = []
    for objects in ((cup,), (moved,), ()):
        scene = PlanningScene(PerceivedScene(_table(), objects))
        scene.set_positions({"arm_lift_joint": 0.2})
        q_grasp = scene.positions()
        scene.set_positions({"arm_lift_joint": 0.3})
        with scene.holding("red", q_grasp, cup):
            assert HELD in scene.geometry
            clearances.append(scene.clearance_at(scene.positions()))
    assert clearances == pytest.approx([0.10 - TABLE_MARGIN - HELD_SPREAD] * 3, abs=2e-3)


def test_only_a_piece_of_the_objects_own_colour_where_it_stood_is_remembered_of_it():
    cup = _cup("red", 0.7, 0.0)
    piece = dataclasses.replace(cup, label="red#2", center=np.array([0.71, 0.01]))
    elsewhere = dataclasses.replace(piece, label="red#3", center=np.array([0.7, 0.2]))
    other_colour = dataclasses.replace(piece, label="blue")
    scene = PlanningScene(PerceivedScene(_table(), (cup, piece, elsewhere, other_colour)))
    assert scene.seen_where_it_stood(cup) == ("red#2",)


def test_the_held_object_seen_again_where_the_hand_has_it_is_left_out():
    """Lifted 10 cm, the cup is seen again as `red#2`, a column from the table up to its top,
    and the hand now starts inside that column: it is the held cup, so it is no obstacle; the
    neighbour 20 cm away, and the same column seen elsewhere, still are."""
    cup, neighbour = _cup("red", 0.7, 0.0), _cup("blue", 0.7, 0.2)
    column = dataclasses.replace(cup, label="red#2", height=cup.height + 0.1)
    elsewhere = dataclasses.replace(column, label="red#3", center=np.array([0.7, -0.2]))
    scene = PlanningScene(PerceivedScene(_table(), (cup, neighbour, column, elsewhere)))
    scene.set_positions({"arm_lift_joint": 0.2})
    q_grasp = scene.positions()
    scene.set_positions({"arm_lift_joint": 0.3})
    q_lifted = scene.positions()
    assert scene.seen_in_hand(cup, scene.hand_pose(q_grasp), q_lifted) == ("red#2",)
    assert scene.seen_in_hand(cup, scene.hand_pose(q_grasp), q_grasp) == ("red#2",)
    with scene.holding("red", q_grasp, cup, q_lifted):
        distances = scene.clearances_at(q_lifted)
    assert set(distances) == {TABLE, "blue", "red#3"}
    with scene.holding("red", q_grasp, cup):  # without the hand's positions now: seen twice
        assert scene.clearances_at(q_lifted)["red#2"] < 0


def test_clearances_name_each_obstacle_a_held_object_comes_near():
    """By obstacle, the held cup's own distances count as the robot's: the neighbour's is the
    held cup's gap to it, never filed under the held object."""
    held, neighbour = _cup("red", 0.7, 0.0), _cup("blue", 0.7, 0.2)
    scene = PlanningScene(PerceivedScene(_table(), (held, neighbour)))
    scene.set_positions({"arm_lift_joint": 0.2})
    q_grasp = scene.positions()
    gap = 0.2 - 2 * (0.035 + OBJECT_MARGIN) - HELD_MARGIN
    with scene.holding("red", q_grasp):
        distances = scene.clearances()
        assert HELD not in distances and distances["blue"] == pytest.approx(gap, abs=1e-3)
        assert scene.clearance() == (distances[TABLE], TABLE)  # its bottom is in the table
        with scene.ignoring(("blue",)):  # ignoring keeps the held cup off it too
            assert "blue" not in scene.clearances()


def test_a_copy_of_the_context_leaves_out_more_than_the_scene_does():
    """For the optimiser's constraints on the obstacles a path starts in contact with."""
    held, neighbour = _cup("red", 0.7, 0.0), _cup("blue", 0.7, 0.2)
    scene = PlanningScene(PerceivedScene(_table(), (held, neighbour)))
    scene.set_positions({"arm_lift_joint": 0.2})
    q_grasp = scene.positions()
    with scene.holding("red", q_grasp):
        root, plant_context = scene.ignoring_context([TABLE])
        query = scene.plant.get_geometry_query_input_port().Eval(plant_context)
        near = query.ComputeSignedDistancePairwiseClosestPoints(NEAR)
        owners = {scene.query().inspector().GetName(gid) for p in near for gid in (p.id_A, p.id_B)}
        assert not any(name.startswith(TABLE) for name in owners)
        assert any(name.startswith("blue") for name in owners)  # the copy sees the held cup
        assert TABLE in scene.clearances()  # and the scene itself is as it was
        with scene.ignoring(("blue",)):  # what the scene ignores now, the copy ignores too
            _, copy = scene.ignoring_context([TABLE])
            query = scene.plant.get_geometry_query_input_port().Eval(copy)
            assert not query.ComputeSignedDistancePairwiseClosestPoints(NEAR)
    del root
