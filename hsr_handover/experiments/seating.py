"""A drawn person starts clear of the table: the experiments vary where each trial's person
sits or stands (`person.variation.position_sd`), and a draw toward a table the layout puts the
person near can put them into it (4 of 30 intent trials on `staggered_high_four.yaml`, seed 1,
failed so). A person sits back until clear, as people push their chair back."""

from __future__ import annotations

import math

from hsr_handover.scenario import Scenario
from hsr_handover.world.station import build_station, initial_overlaps

BACK_BEYOND = 0.01  # m the person sits back beyond the overlap measured
MOST_MOVES = 5  # tries before the run is left to fail with the scenario's own error


def sit_clear(scenario: Scenario) -> float:
    """Move the person (in place) back from where they face until nothing the scenario's
    `person.position` places overlaps the table at the start; returns how far (m), 0 when
    nothing did. Costs one station build (about 0.5 s) per call, beside a trial's 50-100 s."""
    person, moved = scenario.person, 0.0
    for _ in range(MOST_MOVES):
        overlaps = initial_overlaps(build_station(scenario))
        depth = max((o.depth for o in overlaps if o.key == "person.position"), default=0.0)
        if depth == 0.0:
            break
        step = depth + BACK_BEYOND
        x, y = person.position
        person.position = [x - step * math.cos(person.yaw), y - step * math.sin(person.yaw)]
        moved += step
    return moved
