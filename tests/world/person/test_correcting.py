"""The person who sees the robot lift the wrong object asks again (the world side of a
correction): the corrector, the request made again, and a receiver that takes only what it
asked for."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.scenario import load_scenario
from hsr_handover.world.person.behavior import posture_changes
from hsr_handover.world.person.body import BodyDimensions
from hsr_handover.world.person.correcting import Corrector
from hsr_handover.world.person.receiving import (
    RAISED,
    STILL_S,
    Receiver,
    Receiving,
    ReceivingParams,
)
from hsr_handover.world.station.world import (
    CORRECTION_STREAM,
    person_actions,
    request_again,
    wanted_object,
)
from tests.paths import SCENARIOS

BODY = BodyDimensions.from_height(1.7, seated=True)
SHOULDER = BODY.shoulder("right")
TABLE = {"red": np.array([0.8, -0.2, 0.75]), "blue": np.array([0.8, 0.2, 0.75])}
CHANGES = [(0.0, np.zeros(3)), (0.7, np.ones(3))]


def _lifted(name: str, height: float) -> dict[str, np.ndarray]:
    return {**TABLE, name: TABLE[name] + [0.0, 0.0, height]}


def test_another_object_lifted_makes_the_person_ask_again_after_the_reaction_time_once():
    corrector = Corrector("blue", CHANGES, reaction_s=0.5)
    assert corrector.update(0.0, TABLE) == []
    assert corrector.update(1.0, _lifted("red", RAISED - 0.005)) == []  # not yet off the table
    changes = corrector.update(1.05, _lifted("red", RAISED))
    assert [time for time, _ in changes] == pytest.approx([1.55, 2.25])
    assert corrector.corrected_at == 1.05
    assert corrector.update(1.1, _lifted("red", 0.1)) == []  # once


def test_the_object_asked_for_lifted_is_no_mistake_and_nothing_asked_never_corrects():
    corrector = Corrector("blue", CHANGES, reaction_s=0.5)
    corrector.update(0.0, TABLE)
    assert corrector.update(1.0, _lifted("blue", 0.1)) == []
    nothing = Corrector("", CHANGES, reaction_s=0.5)
    nothing.update(0.0, TABLE)
    assert nothing.update(1.0, _lifted("red", 0.1)) == []


def test_a_person_who_asked_for_an_object_does_not_take_another():
    offered = SHOULDER + [0.4, 0.05, -0.05]
    for wanted, reaches in (("cup", True), ("box", False), ("", True)):
        receiver = Receiver(BODY, ReceivingParams(reaction_s=0.2), wanted=wanted)
        receiver.update(0.0, {"cup": offered - [0.0, 0.0, 0.2]}, SHOULDER)
        for time in np.arange(0.05, 0.1 + 2 * STILL_S, 0.05):
            receiver.update(float(time), {"cup": offered}, SHOULDER)
        assert (receiver.state is Receiving.REACHING) is reaches, wanted


def test_the_request_made_again_is_the_scripts_last_with_an_arm_of_its_own():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    script = person_actions(scenario, BODY)
    point = next(action for action in script if action.kind == "point_at")
    look = next(action for action in script if action.kind == "look_at")
    again = request_again(scenario, BODY, CORRECTION_STREAM)
    assert [action.kind for action in again] == ["look_at", "point_at"]
    assert again[0].start == 0.0 and again[1].start == pytest.approx(point.start - look.start)
    assert again[1].end - again[1].start == pytest.approx(point.end - point.start)
    np.testing.assert_allclose(again[1].point, point.point)  # the same object
    assert again[1].head_fraction == point.head_fraction  # the same person
    assert not np.allclose(again[1].arm_point, point.arm_point)  # a gesture of its own
    assert wanted_object(scenario) == scenario.person.behavior[-1].target
    assert person_actions(scenario, BODY)[1].arm_point == pytest.approx(point.arm_point)


def test_nothing_asked_means_nothing_to_ask_again():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.person.behavior = [item for item in scenario.person.behavior
                                if item.action != "point_at"]  # fmt: skip
    assert request_again(scenario, BODY, CORRECTION_STREAM) == [] and wanted_object(scenario) == ""


def test_the_request_made_again_moves_like_the_first():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    again = request_again(scenario, BODY, CORRECTION_STREAM)
    changes = posture_changes(BODY, again, scenario.table.height)
    times = [time for time, _ in changes]
    assert times == sorted(times) and times[0] == 0.0
    assert times[-1] == pytest.approx(again[1].end, abs=2.0)  # it lowers the arm at the end
