"""Scoring plans against the world as it truly is: the station's own geometry."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from hsr_handover.experiments.true_clearance import TrueClearance
from hsr_handover.hsr import add_hsr
from hsr_handover.robot.planning.timing import joint_limits
from hsr_handover.scenario import load_scenario
from hsr_handover.world.station import build_station
from tests.paths import SCENARIOS


@pytest.fixture(scope="module")
def truth():
    station = build_station(load_scenario(SCENARIOS / "intent_reference.yaml"))
    plant = MultibodyPlant(0.01)
    add_hsr(plant, Parser(plant))
    plant.Finalize()
    names = list(joint_limits(plant).names)  # the plant's position order
    return TrueClearance(station, station.diagram.CreateDefaultContext(), names), names


def test_the_true_table_is_where_the_scenario_puts_it(truth):
    clearance, names = truth
    q = np.zeros(len(names))
    q[names.index("wrist_flex_joint")] = -1.57  # the hand tucked, as the robot stands ready
    far, nearest = clearance(q)
    assert nearest == "table" and far > 0.1
    q[names.index("base_x_joint")] = 0.05
    closer, _ = clearance(q)
    assert closer == pytest.approx(far - 0.05, abs=2e-3)
    q[names.index("base_x_joint")] = far + 0.03
    inside, nearest = clearance(q)
    assert nearest == "table" and inside < 0  # penetration: the shortest way out


def _hand_at_green_cup(names: list[str], lift: float) -> np.ndarray:
    """The hand at the green cup (0.80, 0), its arm lift `lift` (m)."""
    q = np.zeros(len(names))
    for joint, value in {"base_x_joint": 0.22, "base_y_joint": -0.078, "arm_lift_joint": lift,
                         "arm_flex_joint": -1.57, "wrist_flex_joint": -0.1}.items():  # fmt: skip
        q[names.index(joint)] = value
    return q


def test_an_ignored_object_is_left_out(truth):
    clearance, names = truth
    q = _hand_at_green_cup(names, 0.45)  # nearest the green cup unless it is ignored
    touching, nearest = clearance(q)
    ignored, other = clearance(q, ignore=("green_cup",))
    assert nearest == "green_cup" and other != "green_cup" and ignored > touching


def test_a_held_object_rides_in_the_hand_and_is_scored(truth):
    clearance, names = truth
    # The hand closed round the green cup 3 cm above its foot, which stands on the table.
    q_grasp = _hand_at_green_cup(names, 0.48)
    before = clearance(q_grasp)
    lowered = q_grasp.copy()
    lowered[names.index("arm_lift_joint")] -= 0.02
    alone, _ = clearance(lowered, ignore=("green_cup",))
    with clearance.holding("green_cup", q_grasp):
        sunk, into = clearance(lowered)
        at_grasp, nearest = clearance(q_grasp)
    assert alone > 0.005  # the hand alone stays above the table
    assert into == "table" and sunk == pytest.approx(-0.02, abs=0.003)  # the cup's foot sinks
    assert nearest != "green_cup" and at_grasp > -0.003  # held, it is no obstacle to the hand
    assert clearance(q_grasp) == before  # let go, the cup is back where it stood
