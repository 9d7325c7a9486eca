"""Every bundled scenario for its whole duration (slow: select with `pytest -m slow`)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover import interface
from hsr_handover.hsr import (
    COMMANDED_JOINTS,
    GRIPPER_KEY,
    HEAD_JOINTS,
    PALM_FRAME,
    hsr_set_positions,
)
from hsr_handover.robot.handover.cycle_types import Phase
from hsr_handover.scenario import load_scenario, object_center
from hsr_handover.simulation import run_scenario
from tests.paths import bundled_scenarios


@pytest.mark.slow
@pytest.mark.parametrize("path", bundled_scenarios(), ids=lambda p: p.name)
def test_bundled_scenario_runs_to_the_end_with_the_world_at_rest(path, tmp_path):
    scenario = load_scenario(path)
    report = run_scenario(scenario, replay=tmp_path / "replay.html")
    asked = [item.target for item in scenario.person.behavior if item.action == "point_at"]
    if scenario.handover.enabled and asked:  # it ends when done, the object asked for handed over
        assert report.cycle.phase is Phase.DONE, (report.cycle.failure, report.cycle.reason)
        assert report.person_holds == asked[-1]
        assert report.replay.stat().st_size > 1_000_000
        return
    if scenario.handover.enabled:  # nobody asks for anything: it fetches nothing
        assert report.intent.target is None, (report.intent.target, report.intent.recognised_time)
    # The world rests to the end.
    assert report.sim_time == pytest.approx(scenario.simulation.duration)
    assert report.replay.stat().st_size > 1_000_000
    plant = report.simulation.station.plant
    plant_context = plant.GetMyContextFromRoot(report.context)
    for obj in scenario.objects:
        position = plant.GetBodyByName(obj.name).EvalPoseInWorld(plant_context).translation()
        assert np.linalg.norm(position - object_center(scenario, obj)) < 3e-3, obj.name
    # The robot turns its head and may raise its torso to watch, the arm folded down
    # (docs/handover.md, "Where it watches from"): its hand rests where its last command puts it.
    robot_context = report.simulation.robot_context(report.context)
    command = report.simulation.robot.diagram.GetOutputPort(interface.HSR_DESIRED_STATE).Eval(
        robot_context
    )
    n = len(COMMANDED_JOINTS)
    body = [row for row, joint in enumerate(COMMANDED_JOINTS) if joint not in HEAD_JOINTS]
    assert np.allclose(command[n:][body], 0.0)  # the body holds a posture, not a motion
    positions = dict(zip(COMMANDED_JOINTS, command[:n], strict=True))
    positions[GRIPPER_KEY] = report.simulation.measured_positions(report.context)[GRIPPER_KEY]
    commanded = plant.CreateDefaultContext()
    hsr_set_positions(plant, commanded, report.simulation.station.robot, positions)
    palm = plant.GetFrameByName(PALM_FRAME)
    drift = (
        palm.CalcPoseInWorld(plant_context).translation()
        - palm.CalcPoseInWorld(commanded).translation()
    )
    assert np.linalg.norm(drift) < 1e-3
