"""What the intent recogniser was given, frame by frame: recorded during a run, replayed offline
with other thresholds (`benchmarks/sweep_intent.py`), reaching the same recognition at the same
time when the thresholds are the same."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from pydrake.systems.framework import Context, EventStatus

from hsr_handover.robot.intent import IntentParams, IntentState, IntentTracker
from hsr_handover.robot.perception.cross_check import confirmed_candidates
from hsr_handover.simulation import Simulation
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S


@dataclasses.dataclass(frozen=True)
class PerceivedFrame:
    """What the intent estimator was given for one camera frame: the capture time, the lifted
    skeleton's points (18 x 3) and confidences, the confirmed (label, centre) candidates and
    the chest's and the face's facing from the depth image (3,; NaN: not seen)."""

    time: float
    points: np.ndarray
    confidence: np.ndarray
    candidates: tuple[tuple[str, np.ndarray], ...]
    torso_forward: np.ndarray = dataclasses.field(default_factory=lambda: np.full(3, np.nan))
    face_forward: np.ndarray = dataclasses.field(default_factory=lambda: np.full(3, np.nan))


class PerceptRecorder:
    """A simulator monitor that keeps the intent estimator's inputs of every camera frame, so
    other thresholds can be tried offline on the same percepts (`replay_intent`)."""

    def __init__(self, simulation: Simulation):
        self._simulation, self._last = simulation, math.nan
        self.frames: list[PerceivedFrame] = []

    def __call__(self, context: Context) -> EventStatus:
        robot = self._simulation.robot.diagram
        robot_context = self._simulation.robot_context(context)
        station = self._simulation.station.diagram
        image_time = station.GetOutputPort("camera_image_time").Eval(
            self._simulation.station_context(context)
        )
        # Once the estimator has judged the new frame (see frame_timing), as it saw it.
        if image_time != self._last and context.get_time() >= image_time + 2 * PROCESSING_DELAY_S:
            self._last = image_time
            skeleton = robot.GetOutputPort("skeleton").Eval(robot_context)
            detections = robot.GetOutputPort("detections").Eval(robot_context).detections
            support = robot.GetOutputPort("detection_support").Eval(robot_context)
            candidates = tuple(confirmed_candidates(detections, support))
            self.frames.append(
                PerceivedFrame(
                    image_time,
                    skeleton.points,
                    skeleton.confidence,
                    candidates,
                    skeleton.torso_forward,
                    skeleton.face_forward,
                )
            )
        return EventStatus.Succeeded()


def replay_intent(frames: Sequence[PerceivedFrame], params: IntentParams) -> IntentState:
    """The intent recogniser run offline over recorded frames: its state after the last."""
    tracker = IntentTracker(params)
    for frame in frames:
        tracker.update(
            frame.time,
            frame.points,
            frame.confidence,
            frame.candidates,
            frame.torso_forward,
            frame.face_forward,
        )
    return tracker.state_
