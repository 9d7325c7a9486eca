"""HandoverSupervisor on its own ports and context: the look round, the ready posture, and a
request it cannot reach ending in a clear failure (never an exception)."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.joint_trajectory import ARM_CONTROLLER, BASE_CONTROLLER
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.person_map import STEADY_FRAMES
from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import Failure, Phase
from hsr_handover.robot.handover.look_round import (
    LOOK_AROUND_PANS,
    LOOK_DWELL_S,
    LOOK_ROUND_S,
    LOOK_ROUND_TILT,
)
from hsr_handover.robot.intent import IntentParams, IntentState
from hsr_handover.robot.perception.object_detection import Detection, DetectionResult
from hsr_handover.robot.perception.object_shapes import BOX, ObjectShape
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.systems.handover_supervisor import VIEW_AFTER_S, HandoverSupervisor
from tests.robot.intent.synthetic_person import keypoints

PAN = COMMANDED_JOINTS.index("head_pan_joint")
OPENING = 0.02
PARAMS = CycleParams()


@pytest.fixture
def supervisor():
    return _supervisor()


def _supervisor(params: IntentParams | None = None):
    ready = np.zeros(2 * len(COMMANDED_JOINTS))
    ready[COMMANDED_JOINTS.index("wrist_flex_joint")] = -1.57
    system = HandoverSupervisor(load_or_build()[0], ready, OPENING, params)
    context = system.CreateDefaultContext()
    system.GetInputPort("hsr_state_measured").FixValue(context, ready)
    system.GetInputPort("gripper_opening_measured").FixValue(context, [OPENING])
    system.GetInputPort("hsr_wrist_wrench_measured").FixValue(context, np.zeros(6))
    system.GetInputPort("intent").FixValue(context, IntentState())
    system.GetInputPort("perceived_scene").FixValue(context, PerceivedScene(None))
    system.GetInputPort("skeleton").FixValue(context, Skeleton.missing("no person"))
    system.GetInputPort("detections").FixValue(context, DetectionResult((), "no detections"))
    return system, context, ready


def _command(system, context) -> np.ndarray:
    return system.GetOutputPort("hsr_desired_state").Eval(context)


def test_it_looks_round_the_table_then_holds_the_ready_posture(supervisor):
    system, context, ready = supervisor
    simulator = Simulator(system, context)
    for stop, pan in enumerate(LOOK_AROUND_PANS):
        simulator.AdvanceTo((stop + 0.5) * LOOK_DWELL_S)
        assert _command(system, context)[PAN] == pan
        assert system.GetOutputPort("watching").Eval(context)[0] == 1.0
    simulator.AdvanceTo(LOOK_ROUND_S + 1.0)
    np.testing.assert_allclose(_command(system, context), ready)
    assert system.GetOutputPort("watching").Eval(context)[0] == 1.0
    assert system.GetOutputPort("gripper_desired_opening").Eval(context)[0] == OPENING
    assert system.GetOutputPort("cycle").Eval(context).phase is Phase.WATCH
    view = system.GetOutputPort("plan_view").Eval(context)  # nothing planned, nothing to draw
    assert view.handover_point is None and view.palm_path.shape == (0, 3)


def test_a_request_for_an_object_it_never_perceived_fails_as_unreachable(supervisor):
    system, context, ready = supervisor
    system.GetInputPort("intent").FixValue(context, IntentState(target="purple"))
    # It looks for the object for seek_s, then plans for patience_s.
    Simulator(system, context).AdvanceTo(LOOK_ROUND_S + PARAMS.seek_s + PARAMS.patience_s + 1.0)
    cycle = system.GetOutputPort("cycle").Eval(context)
    assert cycle.phase is Phase.FAILED and cycle.failure is Failure.UNREACHABLE
    assert cycle.target == "purple" and "purple" in cycle.reason
    assert system.GetOutputPort("watching").Eval(context)[0] == 0.0  # done watching


def test_the_persons_arm_faces_the_way_the_chest_faced_while_it_watched(supervisor):
    """The receiving arm's frame takes the chest's facing voted over the watch's frames, not
    the shoulders' line; once the robot acts (its arm may cover the chest) no vote is added."""
    system, context, _ = supervisor
    points, confidence = keypoints()  # shoulders square to -x
    turn = np.radians(15.0)
    facing = np.array([-np.cos(turn), -np.sin(turn), 0.0])
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence, torso_forward=facing)
    system.GetInputPort("skeleton").FixValue(context, skeleton)
    Simulator(system, context).AdvanceTo(0.55)
    memory = system.memory(context)
    np.testing.assert_allclose(memory.arms[0].frame[:, 0], facing, atol=1e-9)
    memory.machine.record.phase = Phase.APPROACH  # acting: the chest may read the robot's arm
    wrong = Skeleton(np.zeros((18, 2)), points, confidence, torso_forward=np.array([0, 1.0, 0]))
    system.GetInputPort("skeleton").FixValue(context, wrong)
    Simulator(system, context).AdvanceTo(1.55)
    memory = system.memory(context)
    np.testing.assert_allclose(memory.facing.direction(), facing, atol=1e-9)
    np.testing.assert_allclose(memory.arms[0].frame[:, 0], facing, atol=1e-9)


def test_one_frame_with_a_shoulder_lifted_onto_a_held_object_leaves_the_persons_arm(supervisor):
    """The pose detector can put a shoulder onto the object the robot holds up in front of the
    camera, a quarter metre toward it: the arm the cycle plans for keeps the shoulder the last
    second's frames agree on."""
    system, context, _ = supervisor
    points, confidence = keypoints()
    seated = Skeleton(np.zeros((18, 2)), points, confidence)
    system.GetInputPort("skeleton").FixValue(context, seated)
    simulator = Simulator(system, context)
    simulator.AdvanceTo(1.05)
    steady = system.memory(context).arms[0].shoulder.copy()
    lifted = points.copy()
    lifted[keypoint_index("r_shoulder"), 0] -= 0.26  # toward the robot: the person faces -x
    system.GetInputPort("skeleton").FixValue(context, Skeleton(seated.pixels, lifted, confidence))
    simulator.AdvanceTo(1.15)  # one tick on the lifted frame
    memory = system.memory(context)
    assert len(memory.skeletons) == STEADY_FRAMES
    np.testing.assert_allclose(memory.arms[0].shoulder, steady, atol=0.02)


_PLACES = {"red": (0.78, -0.3), "yellow": (0.92, -0.08), "green": (0.8, 0.14)}


def _boxes(table: float, labels=tuple(_PLACES)) -> tuple[ObjectShape, ...]:
    """Boxes 12 cm tall standing on a table `table` m high, between the robot and the person."""
    return tuple(
        ObjectShape(label, BOX, np.array(_PLACES[label]), np.array([0.06, 0.06]), 0.0, table, 0.12)
        for label in labels
    )


def _watched_from(system, context, objects, until: float = VIEW_AFTER_S + 4.0) -> np.ndarray:
    """The command once the look round is over, with the synthetic person seated behind the
    `objects` (perceived), and the joints where they were commanded."""
    points, confidence = keypoints()
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence, torso_forward=np.array([-1.0, 0, 0]))
    system.GetInputPort("skeleton").FixValue(context, skeleton)
    system.GetInputPort("perceived_scene").FixValue(context, PerceivedScene(None, objects))
    simulator = Simulator(system, context)
    for time in np.arange(context.get_time() + 0.05, until, 0.1):  # the joints follow
        simulator.AdvanceTo(time)
        system.GetInputPort("hsr_state_measured").FixValue(context, _command(system, context))
    return _command(system, context)


def test_it_watches_from_a_raised_torso_when_the_objects_would_hide_a_pointing_arm(supervisor):
    system, context, ready = supervisor
    command = _watched_from(system, context, _boxes(0.86))
    lift, flex = (COMMANDED_JOINTS.index(joint) for joint in ("arm_lift_joint", "arm_flex_joint"))
    assert command[lift] > 0.1  # raised ...
    assert command[flex] < -2.5  # ... with the arm folded down out of the camera's view
    n = len(COMMANDED_JOINTS)
    np.testing.assert_allclose(command[n:], 0.0, atol=1e-6)  # and arrived there
    assert system.GetOutputPort("cycle").Eval(context).phase is Phase.WATCH


def test_it_watches_from_the_ready_posture_over_a_low_table(supervisor):
    system, context, ready = supervisor
    np.testing.assert_allclose(_watched_from(system, context, _boxes(0.72)), ready)


def test_it_rises_later_when_an_object_that_would_hide_the_arm_comes_into_view(supervisor):
    system, context, ready = supervisor
    low = _boxes(0.72, ("red", "green"))
    np.testing.assert_allclose(_watched_from(system, context, low), ready)
    lift = COMMANDED_JOINTS.index("arm_lift_joint")
    # The same objects perceived taller are not weighed again; another one seen is.
    taller = _boxes(0.86, ("red", "green"))
    assert _watched_from(system, context, taller, until=context.get_time() + 1.0)[lift] == 0.0
    more = (*low, *_boxes(0.86, ("yellow",)))
    assert _watched_from(system, context, more, until=context.get_time() + 4.0)[lift] > 0.1


def test_a_request_recognised_while_it_rises_is_planned_for_once_it_has_risen(supervisor):
    """A plan starts at rest where the robot stands: planned mid-rise, the grasp would begin
    with a step in the commanded velocity. The recognition is recorded when it comes."""
    system, context, _ = supervisor
    _watched_from(system, context, _boxes(0.86), until=LOOK_ROUND_S + 0.05)  # it may act
    raised = system.memory(context).view.raised
    assert raised is not None and raised.end > context.get_time() + 0.3  # still rising
    recognised = context.get_time() + 0.1
    system.GetInputPort("intent").FixValue(context, IntentState(target="yellow"))
    (yellow,) = [shape for shape in _boxes(0.86) if shape.label == "yellow"]
    seen = Detection("yellow", "yellow", (0, 0, 1, 1), (0.5, 0.5),
                     np.array([*yellow.center, yellow.bottom + 0.05]), 40)  # fmt: skip
    system.GetInputPort("detections").FixValue(context, DetectionResult((seen,), "ok"))
    _watched_from(system, context, _boxes(0.86), until=raised.end - 0.05)
    cycle = system.GetOutputPort("cycle").Eval(context)
    assert cycle.target == "yellow"
    assert cycle.recognised_time == pytest.approx(recognised, abs=0.11)
    assert cycle.planning_s == 0.0 and cycle.phase is Phase.WATCH
    _watched_from(system, context, _boxes(0.86), until=raised.end + 0.25)
    assert system.GetOutputPort("cycle").Eval(context).planning_s > 0.0


def test_with_a_gaze_it_looks_round_low_then_follows_the_gaze(supervisor):
    system, context, _ = supervisor
    tilt = COMMANDED_JOINTS.index("head_tilt_joint")
    n = len(COMMANDED_JOINTS)
    gaze = np.array([0.3, 0.25, 0.1, -0.2])  # pan, tilt and their rates
    system.GetInputPort("head_command").FixValue(context, gaze)
    simulator = Simulator(system, context)
    simulator.AdvanceTo(0.5 * LOOK_DWELL_S)
    command = _command(system, context)
    assert command[PAN] == LOOK_AROUND_PANS[0] and command[tilt] == LOOK_ROUND_TILT
    simulator.AdvanceTo(LOOK_ROUND_S + 0.5)
    command = _command(system, context)
    np.testing.assert_allclose(command[[PAN, tilt, n + PAN, n + tilt]], gaze)


def test_a_request_for_an_object_out_of_view_turns_the_head_to_where_it_was_seen(supervisor):
    """Watching a standing face, the table is below the view: the head turns to the object
    asked for before the grasp is planned, and plans once the camera shows it."""
    system, context, _ = supervisor
    system.GetInputPort("head_command").FixValue(context, np.array([0.0, 0.4, 0.0, 0.0]))
    objects = _boxes(0.72)
    system.GetInputPort("perceived_scene").FixValue(context, PerceivedScene(None, objects))
    simulator = Simulator(system, context)
    simulator.AdvanceTo(LOOK_ROUND_S + 0.05)
    system.GetInputPort("intent").FixValue(context, IntentState(target="yellow"))
    simulator.AdvanceTo(LOOK_ROUND_S + 0.55)
    tilt = COMMANDED_JOINTS.index("head_tilt_joint")
    assert _command(system, context)[tilt] < -0.15  # 12 degrees down to the box, not the 0.4 up
    cycle = system.GetOutputPort("cycle").Eval(context)
    assert cycle.target == "yellow" and cycle.planning_s == 0.0  # not planned unseen
    (yellow,) = [shape for shape in objects if shape.label == "yellow"]
    seen = Detection("yellow", "yellow", (0, 0, 1, 1), (0.5, 0.5),
                     np.array([*yellow.center, yellow.bottom + 0.06]), 40)  # fmt: skip
    system.GetInputPort("detections").FixValue(context, DetectionResult((seen,), "ok"))
    simulator.AdvanceTo(LOOK_ROUND_S + 0.85)
    assert system.GetOutputPort("cycle").Eval(context).planning_s > 0.0


def test_every_motion_it_starts_is_given_as_the_hsrs_controllers_take_it(supervisor):
    """The raise to where it watches from, then the grasp's move once a request comes: the
    base and the arm from where they stood, at rest, to where they were commanded, at the times
    the planner timed them, on the controllers of the joints it moves."""
    system, context, ready = supervisor
    body = [row for row, joint in enumerate(COMMANDED_JOINTS) if not joint.startswith("head")]
    _watched_from(system, context, _boxes(0.86))
    (raised,) = system.GetOutputPort("commanded_trajectories").Eval(context)
    motion = system.memory(context).view.raised
    assert raised.name == "raise" and raised.start == motion.start
    assert raised.times[0] == 0.0 and raised.times[-1] == pytest.approx(motion.motion.duration)
    assert np.all(np.diff(raised.times) > 0) and len(raised.times) > 10
    np.testing.assert_allclose(raised.positions[0], ready[body], atol=1e-6)
    np.testing.assert_allclose(raised.positions[-1], _command(system, context)[body], atol=1e-6)
    np.testing.assert_allclose(raised.velocities[[0, -1]], 0.0, atol=1e-6)
    topics = [topic for topic, *_ in raised.for_controllers()]
    assert ARM_CONTROLLER in topics and BASE_CONTROLLER not in topics  # it rises where it stands
    system.GetInputPort("intent").FixValue(context, IntentState(target="yellow"))
    (yellow,) = [shape for shape in _boxes(0.86) if shape.label == "yellow"]
    seen = Detection("yellow", "yellow", (0, 0, 1, 1), (0.5, 0.5),
                     np.array([*yellow.center, yellow.bottom + 0.05]), 40)  # fmt: skip
    system.GetInputPort("detections").FixValue(context, DetectionResult((seen,), "ok"))
    _watched_from(system, context, _boxes(0.86), until=context.get_time() + 1.0)
    names = [t.name for t in system.GetOutputPort("commanded_trajectories").Eval(context)]
    assert names == ["raise", "move"]
