"""The wrist's force-torque sensor: on its own ports, and in the station, where at rest it
feels the hand's own weight, in the hand's frame however the wrist is turned."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.multibody.math import SpatialForce
from pydrake.systems.analysis import Simulator

from hsr_handover import interface
from hsr_handover.hsr import COMMANDED_JOINTS, PALM_FRAME
from hsr_handover.robot.builder import ready_command
from hsr_handover.scenario import load_scenario
from hsr_handover.world.station import build_station
from hsr_handover.world.systems.wrist_force_sensor import WristForceSensor
from tests.paths import SCENARIOS

GRAVITY = 9.81
WRENCH = interface.HSR_WRIST_WRENCH_MEASURED


def test_it_reads_the_reaction_at_its_joint_reversed():
    sensor = WristForceSensor(joint_index=1)
    context = sensor.CreateDefaultContext()
    on_hand = SpatialForce([0.1, 0.2, 0.3], [1.0, -2.0, 5.0])
    other = SpatialForce([9.0, 9.0, 9.0], [9.0, 9.0, 9.0])
    sensor.get_input_port().FixValue(context, [other, on_hand, other])
    np.testing.assert_allclose(
        sensor.get_output_port().Eval(context), [-0.1, -0.2, -0.3, -1.0, 2.0, -5.0]
    )


def _hand_mass(plant, robot) -> float:
    names = ("hand_palm_link", "hand_l_finger_link", "hand_r_finger_link")
    return sum(plant.GetBodyByName(name, robot).default_mass() for name in names)


def _wrist_force_in_world(station, context) -> np.ndarray:
    plant = station.plant
    wrench = station.diagram.GetOutputPort(WRENCH).Eval(context)
    palm = plant.GetFrameByName(PALM_FRAME, station.robot)
    return palm.CalcPoseInWorld(plant.GetMyContextFromRoot(context)).rotation() @ wrench[3:]


@pytest.fixture(scope="module")
def station():
    """point_left.yaml's world with the camera slowed: nothing here reads images."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.camera.rate_hz = 1.0
    return build_station(scenario)


def _at_rest(station, joints: dict[str, float]):
    """The station's context after 1 s holding the ready posture changed by `joints`."""
    context = station.diagram.CreateDefaultContext()
    state, opening = ready_command(station.scenario)
    for name, value in joints.items():
        state[COMMANDED_JOINTS.index(name)] = value
    station.diagram.GetInputPort(interface.HSR_DESIRED_STATE).FixValue(context, state)
    station.diagram.GetInputPort(interface.GRIPPER_DESIRED_OPENING).FixValue(context, [opening])
    Simulator(station.diagram, context).AdvanceTo(1.0)
    return context


def test_at_rest_it_feels_the_hands_own_weight_however_the_wrist_is_turned(station):
    weight = _hand_mass(station.plant, station.robot) * GRAVITY
    readings = []
    for joints in ({}, {"wrist_flex_joint": -0.6, "wrist_roll_joint": 1.2}):
        context = _at_rest(station, joints)
        readings.append(station.diagram.GetOutputPort(WRENCH).Eval(context)[3:])
        force = _wrist_force_in_world(station, context)
        np.testing.assert_allclose(force, [0.0, 0.0, -weight], atol=0.05 * weight)
    assert np.linalg.norm(readings[0] - readings[1]) > 0.3 * weight  # in the hand's own frame
