"""Whether a carried object looks held out: once it has stopped, or crawls, after moving; not
as the carry sets off, nor while it moves on."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.offer_watch import OfferWatch

PARAMS = CycleParams()
TICK = 0.1


class Carry:
    """A carry's decisions, the palm moved along y as the test says."""

    def __init__(self):
        self.watch, self.time, self.palm = OfferWatch(PARAMS), 0.0, np.array([1.0, 0.2, 1.0])

    def move(self, seconds: float, speed: float) -> list[bool]:
        """The palm at `speed` m/s for `seconds`: what the watch says at each decision."""
        said = []
        for _ in range(round(seconds / TICK)):
            self.time = round(self.time + TICK, 9)
            self.palm = self.palm + [0.0, speed * TICK, 0.0]
            said.append(self.watch.held_out(self.time, self.palm))
        return said


def test_an_object_stopped_mid_carry_looks_held_out_after_offered_s():
    carry = Carry()
    assert not any(carry.move(1.0, 0.3))
    said = carry.move(0.6, 0.0)
    steps = round(PARAMS.offered_s / TICK)
    assert not any(said[: steps - 1]) and all(said[steps - 1 :])


def test_a_crawling_carry_looks_held_out_and_a_moving_one_does_not():
    carry = Carry()
    carry.move(1.0, 0.3)
    assert all(carry.move(1.0, 0.8 * PARAMS.still_speed)[3:])
    assert not any(carry.move(1.0, 1.5 * PARAMS.still_speed))


def test_an_object_still_where_it_was_lifted_has_not_stopped():
    carry = Carry()
    assert not any(carry.move(1.0, 0.0))  # the carry yet to move off
    assert not any(carry.move(0.2, 0.3))


def test_a_carry_that_moves_on_no_longer_holds_it_out():
    carry = Carry()
    carry.move(1.0, 0.3)
    assert carry.move(0.5, 0.0)[-1]
    assert not any(carry.move(0.5, 0.3))
    assert not carry.move(0.2, 0.0)[-1]  # still again, not yet for offered_s


def test_a_repeated_decision_time_says_nothing():
    watch = OfferWatch(PARAMS)
    palm = np.zeros(3)
    assert not watch.held_out(1.0, palm)
    assert not watch.held_out(1.0, palm + 1.0)
