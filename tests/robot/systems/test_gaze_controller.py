"""The GazeController on its own ports, in a loop with a stand-in head camera whose view
decides what the skeleton shows: a person outside the first view is found, a standing face is
framed."""

from __future__ import annotations

import math

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import BasicVector, DiagramBuilder, LeafSystem

from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.robot.perception.active_gaze import FRAMING, SEARCH, FieldOfView
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.systems.gaze_controller import HEAD_ROWS, GazeController
from tests.robot.perception.test_active_gaze import (
    CAMERA,
    LIMITS,
    VIEW,
    camera_rotation,
    in_view,
    skeleton,
    standing_person,
)


class HeadCameraStandIn(LeafSystem):
    """A head that is where it is commanded, and a camera at CAMERA turned by it that sees the
    keypoints of `person` inside VIEW."""

    def __init__(self, person: dict[str, np.ndarray]):
        super().__init__()
        self._person = person
        self._head = self.DeclareVectorInputPort("head_command", 4)
        n = len(COMMANDED_JOINTS)
        self.DeclareVectorOutputPort("hsr_state_measured", 2 * n, self._state)
        self.DeclareAbstractOutputPort(
            "camera_pose", lambda: AbstractValue.Make(RigidTransform()), self._pose
        )
        self.DeclareAbstractOutputPort(
            "skeleton", lambda: AbstractValue.Make(Skeleton.missing("none")), self._skeleton
        )

    def _pan_tilt(self, context) -> tuple[float, float]:
        command = self._head.Eval(context)
        return float(command[0]), float(command[1])

    def _state(self, context, output: BasicVector) -> None:
        state = np.zeros(2 * len(COMMANDED_JOINTS))
        state[HEAD_ROWS] = self._pan_tilt(context)
        output.SetFromVector(state)

    def _pose(self, context, output: AbstractValue) -> None:
        rotation = RotationMatrix(camera_rotation(*self._pan_tilt(context)))
        output.set_value(RigidTransform(rotation, CAMERA))

    def _skeleton(self, context, output: AbstractValue) -> None:
        head = self._pan_tilt(context)
        seen = {name: p for name, p in self._person.items() if in_view(*head, p)}
        points, confidence = skeleton(seen)
        pixels = np.where(confidence[:, None] > 0, 0.0, np.nan).repeat(2, axis=1)
        output.set_value(Skeleton(pixels, points, confidence))


def closed_loop(person: dict, start_head: tuple[float, float], seconds: float, watch=None):
    """Simulate the controller with the stand-in for `seconds` (`watch` is given the head
    command at every step); the controller, its context and the stand-in's."""
    builder = DiagramBuilder()
    gaze = builder.AddSystem(GazeController(VIEW, LIMITS, start_head))
    camera = builder.AddSystem(HeadCameraStandIn(person))
    builder.Connect(gaze.GetOutputPort("head_command"), camera.GetInputPort("head_command"))
    for name in ("hsr_state_measured", "camera_pose", "skeleton"):
        builder.Connect(camera.GetOutputPort(name), gaze.GetInputPort(name))
    diagram = builder.Build()
    simulator = Simulator(diagram)
    gaze.GetInputPort("detections").FixValue(
        gaze.GetMyMutableContextFromRoot(simulator.get_mutable_context()),
        DetectionResult((), "no detections"),
    )
    if watch is not None:
        simulator.set_monitor(lambda root: watch(
            gaze.GetOutputPort("head_command").Eval(gaze.GetMyContextFromRoot(root))
        ))  # fmt: skip
    simulator.AdvanceTo(seconds)
    root = simulator.get_context()
    return gaze, gaze.GetMyContextFromRoot(root), camera.GetMyContextFromRoot(root)


def test_a_person_outside_the_first_view_is_found_and_framed():
    # 55 degrees to the robot's right: out of the 60-degree view straight ahead.
    person = standing_person(1.2 * math.cos(-0.96), 1.2 * math.sin(-0.96), 1.7)
    assert not any(in_view(0.0, 0.0, point) for point in person.values())
    gaze, context, _ = closed_loop(person, (0.0, 0.0), 6.0)
    state = gaze.GetOutputPort("gaze").Eval(context)
    assert state.mode == FRAMING and 0.5 < state.found_at < 4.0
    pan, tilt, pan_rate, tilt_rate = gaze.GetOutputPort("head_command").Eval(context)
    assert pan < -0.5 and (pan_rate, tilt_rate) == (0.0, 0.0)  # turned right, and still
    for name in ("nose", "r_eye", "l_eye"):
        assert in_view(pan, tilt, person[name])


def test_a_standing_face_above_the_start_view_is_framed():
    person = standing_person(1.4, 0.1, 1.86)
    assert not in_view(0.0, 0.0, person["nose"])
    gaze, context, _ = closed_loop(person, (0.0, 0.0), 2.0)
    pan, tilt, *_ = gaze.GetOutputPort("head_command").Eval(context)
    assert tilt > 0.1
    for name in ("nose", "r_eye", "l_eye", "r_wrist"):
        assert in_view(pan, tilt, person[name])


def test_with_no_one_there_it_keeps_searching_and_holds_the_start_until_it_decides():
    gaze = GazeController(FieldOfView(0.5, 0.4), LIMITS, (0.3, -0.2))
    context = gaze.CreateDefaultContext()
    np.testing.assert_allclose(gaze.GetOutputPort("head_command").Eval(context), [0.3, -0.2, 0, 0])
    gaze, context, _ = closed_loop({}, (0.0, 0.0), 5.0)
    assert gaze.GetOutputPort("gaze").Eval(context).mode == SEARCH
    assert math.isnan(gaze.GetOutputPort("gaze").Eval(context).found_at)


def test_the_head_never_turns_faster_than_the_hsr_allows():
    person = standing_person(1.2 * math.cos(0.9), 1.2 * math.sin(0.9), 1.7)
    rates = []
    closed_loop(person, (0.0, 0.0), 4.0, lambda command: rates.append(np.abs(command[2:]).max()))
    assert len(rates) > 30 and max(rates) > 0.5  # it moved
    assert max(rates) <= 1.0  # the HSR head joints' limit (rad/s)
