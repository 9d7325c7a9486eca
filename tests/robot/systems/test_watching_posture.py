"""WatchingPosture on its own ports and context: the watch-only robot raises its torso where the
objects on a high table would hide a seated person's pointing arm, and not at a low one; the
head follows the gaze's command throughout."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.systems.watching_posture import HEAD_ROWS, WatchingPosture
from tests.robot.handover.test_watch_view import SHOULDERS, _objects, _skeleton

N = len(COMMANDED_JOINTS)
LIFT_ROW = COMMANDED_JOINTS.index("arm_lift_joint")
HEAD = np.array([0.1, -0.2, 0.0, 0.0])


def _ready() -> np.ndarray:
    state = np.zeros(2 * N)
    state[COMMANDED_JOINTS.index("wrist_flex_joint")] = -1.57
    return state


def _watch(table: float, seconds: float) -> tuple[WatchingPosture, Simulator]:
    posture = WatchingPosture(_ready())
    simulator = Simulator(posture)
    context = simulator.get_mutable_context()
    posture.GetInputPort("head_command").FixValue(context, HEAD)
    points, confidence = _skeleton(r_shoulder=SHOULDERS[0], l_shoulder=SHOULDERS[1])
    pixels = np.where(confidence[:, None] > 0, 0.0, np.nan).repeat(2, axis=1)
    posture.GetInputPort("skeleton").FixValue(context, Skeleton(pixels, points, confidence))
    posture.GetInputPort("scene").FixValue(context, PerceivedScene(None, tuple(_objects(table))))
    posture.GetInputPort("hsr_state_measured").FixValue(context, _ready())
    simulator.AdvanceTo(seconds)
    return posture, simulator


def _command(posture: WatchingPosture, simulator: Simulator) -> np.ndarray:
    return posture.GetOutputPort("hsr_desired_state").Eval(simulator.get_context())


@pytest.mark.parametrize("table", [0.80, 0.62])
def test_the_torso_rises_over_a_high_table_and_not_a_low_one(table):
    posture, simulator = _watch(table, 0.05)
    lift = posture.GetOutputPort("watch_lift").Eval(simulator.get_context())[0]
    start = _command(posture, simulator)
    np.testing.assert_allclose(start[HEAD_ROWS], HEAD[:2])  # the gaze's head
    np.testing.assert_allclose(start[[n + N for n in HEAD_ROWS]], HEAD[2:])
    if table < 0.7:
        assert lift == 0.0
        body = [row for row in range(N) if row not in HEAD_ROWS]
        np.testing.assert_allclose(start[body], _ready()[body])
        return
    assert lift > 0.1
    assert start[LIFT_ROW] < 0.01  # the raise begins where the torso is ...
    simulator.AdvanceTo(10.0)
    end = _command(posture, simulator)
    assert end[LIFT_ROW] == pytest.approx(lift)  # ... and holds where it ends
    np.testing.assert_allclose(end[N + LIFT_ROW], 0.0, atol=1e-9)  # at rest there
    np.testing.assert_allclose(end[HEAD_ROWS], HEAD[:2])
