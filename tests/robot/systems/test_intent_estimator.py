"""IntentEstimator on its own ports and context: the dwell in simulated time, the map's
cross-check deciding which detections are candidates, and the rays it reports."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from hsr_handover.robot.intent import IntentParams
from hsr_handover.robot.intent.judging import ARM_MOVING
from hsr_handover.robot.perception.cross_check import DetectionSupport
from hsr_handover.robot.perception.object_detection import Detection, DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.systems.intent_estimator import IntentEstimator
from tests.robot.intent.synthetic_person import CUPS, keypoints


def _params(**values) -> IntentParams:
    """The recogniser's params for a person who points from the first frame: no rise to it is
    asked for (`IntentParams.rise_m`; the tracker's own tests show the rise)."""
    return IntentParams(rise_m=0.0, **values)


def _inputs(target: int = 2):
    points, confidence = keypoints(look_at=CUPS[target][1], point_with="left",
                                   point_at=CUPS[target][1])  # fmt: skip
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    detections = tuple(
        Detection(label, label, (0, 0, 1, 1), (0.5, 0.5), center, 10) for label, center in CUPS
    )
    return skeleton, DetectionResult(detections, "ok")


def _run(system, until: float, support=None, image_time=None, skeleton=None, watching=None):
    context = system.CreateDefaultContext()
    if watching is not None:
        system.GetInputPort("watching").FixValue(context, [watching])
    pointing, detections = _inputs()
    skeleton = pointing if skeleton is None else skeleton
    system.GetInputPort("skeleton").FixValue(context, skeleton)
    system.GetInputPort("detections").FixValue(context, detections)
    if support is not None:
        system.GetInputPort("detection_support").FixValue(context, support)
    if image_time is not None:
        system.GetInputPort("image_time").FixValue(context, image_time)
    Simulator(system, context).AdvanceTo(until)
    return system.GetOutputPort("intent").Eval(context), system.GetOutputPort("rays").Eval(context)


def test_recognises_after_the_dwell_from_its_own_frames():
    system = IntentEstimator(period=0.1, params=_params(t_max=0.3, smoothing_s=0.4))
    unsure, _ = _run(system, 0.15)  # two frames: too few to tell a held arm from a sweep
    assert unsure.candidate is None and unsure.frame.status == ARM_MOVING
    early, _ = _run(system, 0.45)
    assert early.target is None and early.candidate == "blue"
    intent, (pointing, gaze) = _run(system, 0.7)
    assert intent.target == "blue" and 0 < intent.confidence <= 1
    # Frames are judged 2 ms after each capture (0.0, 0.1, ...); the dwell counts from the
    # third, at 0.202 s, the first to span half the 0.4 s window and so show the arm held.
    assert intent.recognised_time == pytest.approx(0.502)
    assert pointing is not None and gaze is not None
    assert pointing.direction[0] < 0 and gaze.direction[0] < 0  # toward the table, from x=1.75


def test_it_judges_no_frame_while_the_robot_is_not_watching():
    system = IntentEstimator(period=0.1, params=_params(t_max=0.3, smoothing_s=0.4))
    resting, (pointing, gaze) = _run(system, 0.7, watching=0.0)
    assert resting.target is None and resting.candidate is None
    assert pointing is None and gaze is None
    watching, _ = _run(system, 0.7, watching=1.0)
    assert watching.target == "blue"


def test_the_skeletons_chest_facing_is_the_torso_the_gaze_turns_from():
    """The eyes' direction is the torso's plus head_gain x the face's turn from it: turning
    the chest by d (the shoulders unchanged) turns the estimated gaze by -(head_gain - 1) d."""
    params = _params(t_max=0.3, smoothing_s=0.4)
    points, confidence = keypoints(look_at=CUPS[2][1])  # looking, no arm raised
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    turn = 0.1
    chest = np.array([-math.cos(turn), -math.sin(turn), 0.0])  # the shoulders say -x exactly
    headings = []
    for facing in (np.full(3, np.nan), chest):
        looking = dataclasses.replace(skeleton, torso_forward=facing)
        _, (_, gaze) = _run(IntentEstimator(period=0.1, params=params), 0.25, skeleton=looking)
        headings.append(math.atan2(gaze.direction[1], gaze.direction[0]))
    shift = (headings[1] - headings[0] + math.pi) % (2 * math.pi) - math.pi
    assert shift == pytest.approx(-(params.head_gain - 1) * turn, abs=1e-6)


def test_the_capture_time_times_the_dwell_when_connected():
    system = IntentEstimator(period=0.1, params=_params(t_max=0.0))
    intent, _ = _run(system, 0.35, image_time=7.0)
    assert intent.recognised_time == 7.0


def test_only_detections_the_map_confirms_are_candidates():
    system = IntentEstimator(period=0.1, params=_params(t_max=0.3))
    support = tuple(DetectionSupport(label, 0 if label == "blue" else 5, 0, label != "blue")
                    for label, _ in CUPS)  # fmt: skip
    intent, _ = _run(system, 0.6, support=support)
    assert intent.target is None  # the pointed-at cup is colour without geometry
    assert intent.frame.status != "pointing"


def test_delay_must_fall_inside_the_period():
    with pytest.raises(ValueError, match="delay"):
        IntentEstimator(period=0.1, delay=0.2)
