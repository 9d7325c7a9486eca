"""CorrectionWatch: while the robot lifts or carries, the person asking for another object."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.handover.correction_watch import CorrectionWatch
from hsr_handover.robot.handover.cycle_types import CycleRecord, Phase
from hsr_handover.robot.intent import IntentParams, IntentState
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from tests.robot.intent.synthetic_person import TRUE_FACE_TILT, keypoints

CUPS = {"green": np.array([0.80, 0.0, 0.77]), "blue": np.array([0.80, 0.22, 0.77])}
RECOGNISED = IntentState("green", 1.0, 3.0, objects=tuple(CUPS.items()))
NOTHING_SEEN = DetectionResult((), "no detections")


def _corrections(phase: Phase, first_target: str | None = None) -> list[str | None]:
    """4 s of the supervisor's ticks in `phase`: 1.5 s resting, then pointing at the blue cup
    (the estimator's params: here the synthetic face's tilt)."""
    watch = CorrectionWatch(IntentParams(face_tilt_deg=TRUE_FACE_TILT))
    record = CycleRecord(phase=phase, target="green", first_target=first_target)
    resting, confidence = keypoints(look_at=CUPS["green"])
    blue, _ = keypoints(look_at=CUPS["blue"], point_with="right", point_at=CUPS["blue"])
    corrections = []
    for step in range(40):
        skeleton = Skeleton(np.zeros((18, 2)), resting if step < 15 else blue, confidence)
        time = 10.0 + 0.1 * step
        corrections.append(watch.update(time, record, RECOGNISED, skeleton, NOTHING_SEEN))
    return corrections


def test_lifting_a_gesture_at_another_object_is_a_correction():
    """It takes over the estimator's objects where last seen: nothing is asked while the
    person rests, the blue cup once they point at it."""
    corrections = _corrections(Phase.LIFT)
    assert corrections[:15] == [None] * 15 and corrections[-1] == "blue"
    assert _corrections(Phase.CARRY)[-1] == "blue"


def test_no_correction_is_read_before_the_lift_or_after_one_was_heeded():
    assert set(_corrections(Phase.APPROACH)) == {None}
    assert set(_corrections(Phase.LIFT, first_target="red")) == {None}


def test_a_reach_for_the_object_held_is_no_correction_for_the_one_behind_it():
    """Carried toward the person, the green cup passes in front of the blue one as they see
    it; they reach for it, eyes on it. Judged where the hand holds it (from the robot's own
    joints), it is the object fetched; judged where it was last seen, on the table, the blue
    cup behind the reach would be read as asked for."""
    held = CUPS["blue"] + 0.4 * (keypoints()[0][0] - CUPS["blue"])  # toward the person's nose
    reaching, confidence = keypoints(look_at=held, point_with="right", point_at=held)
    resting, _ = keypoints(look_at=held)

    def corrections(where: np.ndarray | None) -> set[str | None]:
        watch = CorrectionWatch(IntentParams(face_tilt_deg=TRUE_FACE_TILT))
        record = CycleRecord(phase=Phase.CARRY, target="green")
        seen = set()
        for step in range(40):
            skeleton = Skeleton(np.zeros((18, 2)), resting if step < 15 else reaching, confidence)
            time = 10.0 + 0.1 * step
            seen.add(watch.update(time, record, RECOGNISED, skeleton, NOTHING_SEEN, where))
        return seen

    assert corrections(held) == {None}
    assert corrections(None) == {None, "blue"}
