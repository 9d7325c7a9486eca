"""A trial's drawn person starts clear of the table."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from hsr_handover.experiments.seating import sit_clear
from hsr_handover.scenario import load_scenario
from hsr_handover.station import build_station, initial_overlaps

LAYOUT = Path(__file__).resolve().parents[1] / "scenarios" / "layouts" / "staggered_high_four.yaml"


def test_a_person_drawn_into_the_table_sits_back_until_clear():
    scenario = load_scenario(LAYOUT)
    person = scenario.person
    x, y = person.position
    facing = (math.cos(person.yaw), math.sin(person.yaw))
    drawn = 0.3  # toward the table: the hands rest over its top, the knees reach its edge
    person.position = [x + drawn * facing[0], y + drawn * facing[1]]
    assert initial_overlaps(build_station(scenario))
    moved = sit_clear(scenario)
    assert 0.0 < moved < drawn
    assert not initial_overlaps(build_station(scenario))
    back = [person.position[0] - x, person.position[1] - y]
    assert back[0] * facing[0] + back[1] * facing[1] == pytest.approx(drawn - moved)


def test_a_person_already_clear_stays_where_drawn():
    scenario = load_scenario(LAYOUT)
    where = list(scenario.person.position)
    assert sit_clear(scenario) == 0.0
    assert scenario.person.position == where
