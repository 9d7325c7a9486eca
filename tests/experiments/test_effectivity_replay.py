"""Figs. 8 and 14 drawn in the replay: one switchable Meshcat entry per layer."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.experiments.effectivity.replay import (
    EFFECTIVITY,
    draw_effectivity,
    effectivity_layers,
)
from hsr_handover.replay.meshcat_replay import make_local_meshcat
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.planning.handover_pose import HandoverPose

FACING_MINUS_X = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])


@pytest.fixture(scope="module")
def person() -> PersonEffectivity:
    return PersonEffectivity(HumanArm("r", np.array([1.75, 0.19, 1.03]), FACING_MINUS_X,
                                      0.30, 0.25, 0.09))  # fmt: skip


def _handover() -> HandoverPose:
    nodes = np.array([[1.2, 0.2, 0.95], [1.3, 0.2, 0.95], [0.5, 0.0, 0.9]])
    mutual = np.array([True, True, False])
    return HandoverPose(True, "ok", nodes[0], nodes[1], np.zeros(3), nodes, mutual)


def test_the_layers_split_the_robots_map_at_the_mutual_area(person):
    layers = effectivity_layers(person, _handover())
    assert set(layers) == {"person_range", "arm_map", "mutual_area"}
    np.testing.assert_allclose(layers["mutual_area"], _handover().robot_nodes[:2])
    np.testing.assert_allclose(layers["arm_map"], _handover().robot_nodes[2:])
    assert len(layers["person_range"]) == len(person.nodes)
    # No person seen: nothing of theirs, no mutual area.
    assert effectivity_layers(None, None) == {}


def test_each_layer_and_the_handover_point_is_its_own_meshcat_entry(person):
    meshcat = make_local_meshcat()
    paths = draw_effectivity(meshcat, person, _handover())
    expected = {f"{EFFECTIVITY}/{name}" for name in
                ("person_range", "arm_map", "mutual_area", "handover_point")}  # fmt: skip
    assert set(paths) == expected
    assert all(meshcat.HasPath(path) for path in paths)
    failed = HandoverPose(False, "no mutual area", _handover().ideal)
    assert draw_effectivity(make_local_meshcat(), person, failed) == [f"{EFFECTIVITY}/person_range"]
