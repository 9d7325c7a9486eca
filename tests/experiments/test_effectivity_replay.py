"""Figs. 8 and 14 drawn in the replay: one switchable overlay per layer, the arm's map with its
edges round a robot drawn at the planned handover pose."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.experiments.effectivity.replay import draw_effectivity, effectivity_layers
from hsr_handover.replay.meshcat_replay import make_local_meshcat
from hsr_handover.replay.overlays import (
    ARM_MAP,
    HANDOVER_POINT,
    MUTUAL_AREA,
    PERSON_RANGE,
    PLANNED_ROBOT,
    drawn_overlays,
)
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.planning.handover_pose import HandoverPose
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene
from tests.meshcat_html import meshcat_commands

FACING_MINUS_X = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])


@pytest.fixture(scope="module")
def person() -> PersonEffectivity:
    return PersonEffectivity(HumanArm("r", np.array([1.75, 0.19, 1.03]), FACING_MINUS_X,
                                      0.30, 0.25, 0.09))  # fmt: skip


def _handover(q: np.ndarray | None = None) -> HandoverPose:
    nodes = np.array([[1.2, 0.2, 0.95], [1.3, 0.2, 0.95], [0.5, 0.0, 0.9]])
    mutual = np.array([True, True, False])
    return HandoverPose(
        ok=True, reason="ok", ideal=nodes[0], point=nodes[1], q=q, robot_nodes=nodes, mutual=mutual
    )


def _planned_q() -> np.ndarray:
    """The HSR's positions (the planning scene's order) with its base at (0.9, 0.4, 0.5 rad)."""
    robot = PlanningScene(PerceivedScene(None))
    robot.set_positions({"base_x_joint": 0.9, "base_y_joint": 0.4, "base_yaw_joint": 0.5})
    return robot.positions()


def test_the_layers_split_the_robots_map_at_the_mutual_area(person):
    layers = effectivity_layers(person, _handover())
    assert set(layers) == {"person_range", "arm_map", "mutual_area"}
    np.testing.assert_allclose(layers["mutual_area"], _handover().robot_nodes[:2])
    np.testing.assert_allclose(layers["arm_map"], _handover().robot_nodes[2:])
    assert len(layers["person_range"]) == len(person.nodes)
    # No person seen: nothing of theirs, no mutual area.
    assert effectivity_layers(None, None) == {}


def test_each_layer_the_handover_point_and_the_planned_robot_is_its_own_overlay(person):
    meshcat = make_local_meshcat()
    edges = np.array([[0, 1], [1, 2]])
    paths = draw_effectivity(meshcat, person, _handover(_planned_q()), edges)
    expected = [o.path for o in (PERSON_RANGE, ARM_MAP, MUTUAL_AREA, HANDOVER_POINT, PLANNED_ROBOT)]
    assert paths == expected
    assert {o.path for o in drawn_overlays(meshcat)} == set(expected)  # in the legend
    assert meshcat.HasPath(f"{ARM_MAP.path}/edges")
    failed = HandoverPose(ok=False, reason="no mutual area", ideal=_handover().ideal)
    assert draw_effectivity(make_local_meshcat(), person, failed) == [PERSON_RANGE.path]


def test_the_arm_maps_edges_join_its_nodes_where_the_map_is_placed(person):
    meshcat = make_local_meshcat()
    draw_effectivity(meshcat, person, _handover(), np.array([[0, 2], [1, 2]]))
    path = f"{ARM_MAP.path}/edges"
    (segments,) = [c for c in meshcat_commands(meshcat.StaticHtml())
                   if c.get("path") == path and c["type"] == "set_object"]  # fmt: skip
    packed = segments["object"]["geometries"][0]["data"]["attributes"]["position"]["array"]
    ends = np.frombuffer(packed.data, dtype=np.float32).reshape(-1, 3)  # each start, its end
    np.testing.assert_allclose(ends, _handover().robot_nodes[[0, 2, 1, 2]], atol=1e-6)


def test_the_planned_robot_stands_at_the_planned_base(person):
    meshcat = make_local_meshcat()
    draw_effectivity(meshcat, person, _handover(_planned_q()))
    robot = f"{PLANNED_ROBOT.path}/"
    transforms = [c for c in meshcat_commands(meshcat.StaticHtml())
                  if c["type"] == "set_transform" and c["path"].startswith(robot)]  # fmt: skip
    assert len(transforms) > 10  # the base, the torso, the arm, the head, the hand
    where = np.array([t["matrix"][12:14] for t in transforms])  # column-major 4x4, Drake's frame
    assert np.linalg.norm(np.median(where, axis=0) - [0.9, 0.4]) < 0.3
