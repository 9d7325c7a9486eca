"""A trial's drawn person starts clear of the table."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from hsr_handover.experiments import seating
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.scenario import load_scenario
from hsr_handover.world.station.builder import Overlap

LAYOUT = Path(__file__).resolve().parents[2] / "scenarios" / "layouts" / "staggered_high_four.yaml"


def test_a_person_drawn_into_the_table_sits_back_until_clear(monkeypatch):
    """At rest a person's arms lie over the table's top (`rest_posture`), so the built scene
    of a bundled layout never shows this overlap; the station's measure is stood in for by a
    table edge the person's front (0.25 m before their position) must stay behind."""
    scenario = load_scenario(LAYOUT)
    person = scenario.person
    x, y = person.position
    facing = (math.cos(person.yaw), math.sin(person.yaw))
    drawn = 0.3
    person.position = [x + drawn * facing[0], y + drawn * facing[1]]
    along = lambda point: point[0] * facing[0] + point[1] * facing[1]  # noqa: E731
    edge = along((x, y)) + 0.25 + 0.2  # the front 0.2 m clear where drawn from: 0.1 m in now

    def overlaps(_station):
        depth = along(person.position) + 0.25 - edge
        return (
            [Overlap("person.position", "the person", "the table", depth)] if depth > 1e-3 else []
        )

    monkeypatch.setattr(seating, "initial_overlaps", overlaps)
    monkeypatch.setattr(seating, "build_station", lambda scenario: None)
    moved = sit_clear(scenario)
    assert moved == pytest.approx(0.1 + seating.BACK_BEYOND)
    assert not overlaps(None)
    back = [person.position[0] - x, person.position[1] - y]
    assert back[0] * facing[0] + back[1] * facing[1] == pytest.approx(drawn - moved)


def test_a_person_already_clear_stays_where_drawn():
    scenario = load_scenario(LAYOUT)
    where = list(scenario.person.position)
    assert sit_clear(scenario) == 0.0
    assert scenario.person.position == where
