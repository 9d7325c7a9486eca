"""PlanView: the palm's path sampled along planned motions, and the handover's maps kept
through later plans."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.robot.planning.plan_view import PATH_STEP_S, PlanView, palm_path
from tests.robot.handover.test_cycle import Line


def test_the_path_samples_each_motion_to_its_end():
    motions = [Line([0.0], [1.0], duration=0.25), Line([1.0], [3.0], duration=0.2)]
    path = palm_path(motions, lambda q: np.array([q[0], 0.0, 1.0]))
    xs = path[:, 0]
    first = np.append(np.arange(0.0, 0.25, PATH_STEP_S), 0.25) / 0.25
    second = 1.0 + 2.0 * np.append(np.arange(0.0, 0.2, PATH_STEP_S), 0.2) / 0.2
    np.testing.assert_allclose(xs, np.concatenate([first, second]))
    assert path.shape == (len(xs), 3) and np.all(path[:, 2] == 1.0)


def test_no_motion_is_an_empty_path():
    assert palm_path([], lambda q: np.zeros(3)).shape == (0, 3)


def test_a_later_plan_replaces_the_path_and_keeps_the_handovers_maps():
    handover = PlanView(np.zeros((2, 3)), np.ones((3, 3)), np.array([True, False, True]),
                        np.ones((4, 3)), np.array([1.0, 0.0, 1.0]))  # fmt: skip
    follow = PlanView(np.full((5, 3), 2.0))
    after = handover.updated(follow)
    np.testing.assert_array_equal(after.palm_path, follow.palm_path)
    assert after.handover_point is handover.handover_point
    assert after.arm_nodes is handover.arm_nodes and after.mutual is handover.mutual
    assert handover.updated(None) is handover
    again = PlanView(np.zeros((1, 3)), handover_point=np.array([0.5, 0.5, 1.0]))
    assert follow.updated(again) is again  # a new handover plan brings its own


@pytest.mark.parametrize("field", ["palm_path", "arm_nodes", "person_nodes"])
def test_an_empty_view_has_no_points(field):
    assert getattr(PlanView(), field).shape == (0, 3)
