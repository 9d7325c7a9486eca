"""Whole simulations: the bundled demo, run once for every test that looks at it (its cycle,
its truth, its replay)."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import pytest

from hsr_handover.experiments.handover.scoring import HandoverScorer, TrialScore
from hsr_handover.scenario import Scenario, load_scenario
from hsr_handover.simulation import RunReport, run_scenario
from tests.paths import SCENARIOS


class DemoRun(NamedTuple):
    scenario: Scenario
    report: RunReport
    score: TrialScore  # the truth scorer's, for the box the person asks for
    replay: Path


@pytest.fixture(scope="session")
def demo(tmp_path_factory: pytest.TempPathFactory) -> DemoRun:
    """The bundled demo, run once (about 2 minutes) with the truth scorer watching and its
    replay written."""
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    scorers: list[HandoverScorer] = []

    def scorer(simulation) -> HandoverScorer:
        scorers.append(HandoverScorer(simulation, "yellow_box", scenario.table.height))
        return scorers[-1]

    replay = tmp_path_factory.mktemp("demo") / "demo.html"
    report = run_scenario(scenario, replay=replay, monitor_factory=scorer)
    return DemoRun(scenario, report, scorers[0].score, replay)
