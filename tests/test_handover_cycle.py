"""The whole perceiving-acting cycle end to end on the bundled demo: the robot recognises the
pointed-at box, grasps it by friction, carries it, and the person takes it (about 2 minutes)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.handover.cycle import Phase
from hsr_handover.scenario import load_scenario
from hsr_handover.simulation import run_scenario
from tests.conftest import SCENARIOS


@pytest.fixture(scope="module")
def demo():
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    return scenario, run_scenario(scenario)


def test_the_robot_hands_the_pointed_at_object_over(demo):
    scenario, report = demo
    cycle = report.cycle
    assert cycle.phase is Phase.DONE, (cycle.failure, cycle.reason)
    assert cycle.target == "yellow"  # the box's colour: the robot names objects as it sees them
    assert report.person_holds == "yellow_box"
    assert list(cycle.phase_times) == ["approach", "grasp", "lift", "carry", "present",
                                       "release", "retreat", "done"]  # fmt: skip
    assert report.sim_time < scenario.simulation.duration  # it stops once the robot is done


def test_the_box_ends_in_the_persons_hand_not_on_the_table(demo):
    scenario, report = demo
    plant = report.simulation.station.plant
    context = plant.GetMyContextFromRoot(report.context)
    box = plant.GetBodyByName("yellow_box").EvalPoseInWorld(context).translation()
    hand = plant.GetBodyByName("r_hand").EvalPoseInWorld(context).translation()
    assert np.linalg.norm(box - hand) < 0.2
    assert box[2] > scenario.table.height + 0.1  # held up, not put down or dropped
    for other in ("red_cup", "blue_cup"):  # the others stay where they stood
        moved = plant.GetBodyByName(other).EvalPoseInWorld(context).translation()
        start = next(o for o in scenario.objects if o.name == other).position
        assert np.linalg.norm(moved[:2] - start[:2]) < 0.005
