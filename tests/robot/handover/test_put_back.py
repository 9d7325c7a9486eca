"""Putting an object back: its steps, in the one order they follow."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.robot.handover.put_back import PutBack, PutBackStep


def test_the_steps_follow_one_another_plan_lower_open_leave():
    put = PutBack("red", [np.zeros(3)], since=1.0)
    steps, times = [put.step], [put.since]
    for time in (2.0, 3.5, 4.3):
        put = put.advanced(time)
        steps.append(put.step)
        times.append(put.since)
    assert steps == [PutBackStep.PLAN, PutBackStep.LOWER, PutBackStep.OPEN, PutBackStep.LEAVE]
    assert times == [1.0, 2.0, 3.5, 4.3]
    assert put.next_target == "red" and len(put.came) == 1  # kept throughout


def test_the_object_is_in_the_hand_until_the_fingers_open():
    holding = {step: step.holding for step in PutBackStep}
    assert holding == {PutBackStep.PLAN: True, PutBackStep.LOWER: True,
                       PutBackStep.OPEN: False, PutBackStep.LEAVE: False}  # fmt: skip


def test_there_is_no_step_after_leaving():
    with pytest.raises(ValueError, match="fetches"):
        PutBack("red", [], since=0.0, step=PutBackStep.LEAVE).advanced(1.0)
