"""Plan, Motion and Stopwatch: the one vocabulary of planning, read without Drake."""

from __future__ import annotations

import time

import numpy as np
import pytest

from hsr_handover.robot.planning.plan import Motion, Plan
from hsr_handover.robot.planning.stopwatch import Stopwatch
from tests.robot.handover.test_cycle import Line


def test_a_motion_answers_for_its_trajectory():
    motion = Motion(name="carry", trajectory=Line([0.0, 1.0], [2.0, 3.0], duration=2.0))
    position, velocity = motion.state(1.0)
    np.testing.assert_allclose(position, [1.0, 2.0])
    np.testing.assert_allclose(velocity, [1.0, 1.0])
    assert motion.duration == 2.0 and motion.ignore == ()


def test_a_plan_lasts_its_motions_and_took_its_stages():
    plan = Plan(
        ok=True, reason="ok",
        motions=(Motion(name="move", trajectory=Line([0.0], [1.0], 1.5)),
                 Motion(name="lift", trajectory=Line([1.0], [2.0], 0.5))),
        seconds={"ik": 0.25, "optimisation": 0.5, "timing": 0.125},
    )  # fmt: skip
    assert plan.duration == pytest.approx(2.0)
    assert plan.plan_seconds == pytest.approx(0.875)


def test_plans_are_built_with_keywords_only():
    with pytest.raises(TypeError):
        Plan(True, "ok")  # type: ignore[misc]


def test_the_stopwatch_adds_each_stages_time_and_its_snapshot_stays_put():
    watch = Stopwatch(("ik", "timing"))
    assert watch.seconds == {"ik": 0.0, "timing": 0.0}
    for _ in range(2):
        with watch.stage("ik"):
            time.sleep(0.01)
    taken = watch.snapshot()
    with watch.stage("scene"):
        time.sleep(0.01)
    assert taken["ik"] >= 0.02 and taken["timing"] == 0.0 and "scene" not in taken
    assert watch.seconds["scene"] >= 0.01


def test_a_stage_that_raises_is_still_timed():
    watch = Stopwatch()
    with pytest.raises(RuntimeError), watch.stage("ik"):
        time.sleep(0.01)
        raise RuntimeError("the solver crashed")
    assert watch.seconds["ik"] >= 0.01
