"""The person whose request draws no response asks again (the world side of a repeat): the
repeater on the robot's hand, and the request made again from a stream of its own."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.scenario import load_scenario
from hsr_handover.world.person.body import BodyDimensions
from hsr_handover.world.person.repeating import MOVED, Repeater
from hsr_handover.world.station.world import (
    CORRECTION_STREAM,
    REPEAT_STREAM,
    last_request,
    request_again,
)
from tests.paths import SCENARIOS

BODY = BodyDimensions.from_height(1.7, seated=True)
CHANGES = [(0.0, np.zeros(3)), (0.7, np.ones(3))]
HAND = np.array([0.3, 0.0, 0.7])


def test_a_robot_whose_hand_stays_still_is_asked_again_once_the_wait_is_over():
    repeater = Repeater(CHANGES, ended=5.0, wait_s=6.0)
    assert repeater.update(4.0, HAND + [0.5, 0.0, 0.0]) == []  # before the request ended
    assert repeater.update(5.0, HAND) == []  # where the hand was when it ended
    assert repeater.update(8.0, HAND + [0.0, 0.0, 0.3]) == []  # raised: only up
    assert repeater.update(10.9, HAND + [MOVED * 0.9, 0.0, 0.0]) == []  # not long enough
    changes = repeater.update(11.0, HAND)
    assert [time for time, _ in changes] == pytest.approx([11.0, 11.7])
    assert repeater.repeated_at == 11.0 and not repeater.answered
    assert repeater.update(20.0, HAND) == []  # once


def test_a_robot_that_sets_off_has_answered_and_is_not_asked_again():
    repeater = Repeater(CHANGES, ended=5.0, wait_s=6.0)
    repeater.update(5.0, HAND)
    assert repeater.update(7.0, HAND + [0.0, MOVED, 0.0]) == []
    assert repeater.answered
    assert repeater.update(12.0, HAND) == []  # back where it was: it still responded
    assert repeater.repeated_at is None


def test_the_repeated_request_draws_its_own_pointing_error():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    repeat = request_again(scenario, BODY, REPEAT_STREAM)
    correction = request_again(scenario, BODY, CORRECTION_STREAM)
    assert [action.kind for action in repeat] == ["look_at", "point_at"]
    np.testing.assert_allclose(repeat[1].point, correction[1].point)  # the same object
    assert not np.allclose(repeat[1].arm_point, correction[1].arm_point)
    assert last_request(scenario).target == scenario.person.behavior[-1].target
