"""Every bundled scenario for its whole duration (slow: select with `pytest -m slow`)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import PALM_FRAME
from hsr_handover.robot.handover.cycle_types import Phase
from hsr_handover.scenario import load_scenario, object_center
from hsr_handover.simulation import run_scenario
from tests.paths import bundled_scenarios


@pytest.mark.slow
@pytest.mark.parametrize("path", bundled_scenarios(), ids=lambda p: p.name)
def test_bundled_scenario_runs_to_the_end_with_the_world_at_rest(path, tmp_path):
    scenario = load_scenario(path)
    report = run_scenario(scenario, replay=tmp_path / "replay.html")
    if scenario.handover.enabled:  # the robot acts: it ends when done, the object handed over
        assert report.cycle.phase is Phase.DONE, (report.cycle.failure, report.cycle.reason)
        assert report.replay.stat().st_size > 1_000_000
        return
    assert report.sim_time == pytest.approx(scenario.simulation.duration)
    assert report.replay.stat().st_size > 1_000_000
    plant = report.simulation.station.plant
    plant_context = plant.GetMyContextFromRoot(report.context)
    for obj in scenario.objects:
        position = plant.GetBodyByName(obj.name).EvalPoseInWorld(plant_context).translation()
        assert np.linalg.norm(position - object_center(scenario, obj)) < 3e-3, obj.name
    fresh = plant.CreateDefaultContext()
    palm = plant.GetFrameByName(PALM_FRAME)
    drift = (
        palm.CalcPoseInWorld(plant_context).translation()
        - palm.CalcPoseInWorld(fresh).translation()
    )
    assert np.linalg.norm(drift) < 1e-3
